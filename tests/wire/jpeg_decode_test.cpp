#include "semfuse/wire/jpeg_decode.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace semfuse::wire {
namespace {

// A colour image with edges and gradients in every channel, so that chroma subsampling and the
// upsampling filter matter.
cv::Mat texturedBgr(int width, int height) {
  cv::Mat bgr(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      bgr.at<cv::Vec3b>(y, x) =
          cv::Vec3b(static_cast<uint8_t>((x * 7 + y * 3) & 0xFF), static_cast<uint8_t>(((x / 5) % 2) * 200 + y % 50),
                    static_cast<uint8_t>((x * y) % 251));
  return bgr;
}

std::vector<uint8_t> encodeJpeg(const cv::Mat& image, bool progressive = false) {
  std::vector<uint8_t> bytes;
  EXPECT_TRUE(
      cv::imencode(".jpg", image, bytes, {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_PROGRESSIVE, progressive}));
  return bytes;
}

cv::Mat openCvRgb(const std::vector<uint8_t>& bytes, int flags = cv::IMREAD_COLOR) {
  cv::Mat decoded = cv::imdecode(bytes, flags), rgb;
  cv::cvtColor(decoded, rgb, cv::COLOR_BGR2RGB);
  return rgb;
}

TEST(JpegDecode, SamePixelsAsOpenCvBaselineAndProgressive) {
  const cv::Mat bgr = texturedBgr(64, 48);
  for (bool progressive : {false, true}) {
    const auto bytes = encodeJpeg(bgr, progressive);
    int warnings = -1;
    auto rgb = decodeJpegRgb(bytes.data(), bytes.size(), {64, 48}, &warnings);
    ASSERT_TRUE(rgb.ok()) << rgb.error();
    EXPECT_EQ(rgb.value().type(), CV_8UC3);
    EXPECT_EQ(warnings, 0);
    EXPECT_EQ(cv::norm(rgb.value(), openCvRgb(bytes), cv::NORM_INF), 0.0) << "progressive " << progressive;
  }
}

TEST(JpegDecode, GreyscaleComesOutAsEqualChannels) {
  cv::Mat grey;
  cv::cvtColor(texturedBgr(32, 16), grey, cv::COLOR_BGR2GRAY);
  const auto bytes = encodeJpeg(grey);
  auto rgb = decodeJpegRgb(bytes.data(), bytes.size(), {32, 16});
  ASSERT_TRUE(rgb.ok()) << rgb.error();
  const cv::Mat expected = cv::imdecode(bytes, cv::IMREAD_GRAYSCALE);
  cv::Mat channels[3];
  cv::split(rgb.value(), channels);
  for (const cv::Mat& channel : channels) EXPECT_EQ(cv::norm(channel, expected, cv::NORM_INF), 0.0);
}

TEST(JpegDecode, GreyStaysOneChannelWhenAskedAndColourIsRgb) {
  cv::Mat grey;
  cv::cvtColor(texturedBgr(32, 16), grey, cv::COLOR_BGR2GRAY);
  const auto grey_jpeg = encodeJpeg(grey);
  auto one = decodeJpegRgbOrGrey(grey_jpeg.data(), grey_jpeg.size(), {32, 16});
  ASSERT_TRUE(one.ok()) << one.error();
  ASSERT_EQ(one.value().type(), CV_8UC1);
  EXPECT_TRUE(one.value().isContinuous());
  EXPECT_EQ(cv::norm(one.value(), cv::imdecode(grey_jpeg, cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
  const auto colour_jpeg = encodeJpeg(texturedBgr(32, 16));
  auto three = decodeJpegRgbOrGrey(colour_jpeg.data(), colour_jpeg.size(), {32, 16});
  ASSERT_TRUE(three.ok()) << three.error();
  EXPECT_EQ(cv::norm(three.value(), openCvRgb(colour_jpeg), cv::NORM_INF), 0.0);
}

TEST(JpegDecode, OtherSizeThanExpectedIsRefused) {
  const auto bytes = encodeJpeg(texturedBgr(20, 10));
  EXPECT_EQ(decodeJpegRgb(bytes.data(), bytes.size(), {64, 48}).error(), "JPEG payload declares 20x10, expected 64x48");
}

TEST(JpegDecode, BrokenHeadersAreErrorsWithLibjpegsMessage) {
  EXPECT_EQ(decodeJpegRgb(nullptr, 0, {8, 8}).error(), "empty JPEG payload");
  const std::vector<uint8_t> garbage = {0x12, 0x34, 0x56, 0x78, 0x9a, 0xbc};
  auto bad = decodeJpegRgb(garbage.data(), garbage.size(), {8, 8});
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("JPEG payload does not decode: Not a JPEG file"), std::string::npos) << bad.error();
  // Cut inside the headers: no frame to decode.
  const auto bytes = encodeJpeg(texturedBgr(16, 16));
  auto cut = decodeJpegRgb(bytes.data(), 100, {16, 16});
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.error().rfind("JPEG payload does not decode: ", 0), 0u) << cut.error();
}

TEST(JpegDecode, TruncatedOrDamagedScansAreRefused) {
  // libjpeg (and cv::imdecode) would decode these, with made-up pixels where data is missing or
  // damaged, and only warn: the colour a frame would then paint into the map is refused.
  const auto bytes = encodeJpeg(texturedBgr(64, 64));
  auto cut = decodeJpegRgb(bytes.data(), bytes.size() * 3 / 4, {64, 64});
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.error(), "JPEG payload does not decode: damaged data (Premature end of JPEG file)");
  // An end-of-image marker in the middle of the entropy-coded data.
  std::size_t scan = 0;
  for (std::size_t i = 0; i + 1 < bytes.size(); ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xDA) scan = i;
  ASSERT_GT(scan, 0u);
  std::vector<uint8_t> damaged(bytes);
  const std::size_t middle = scan + (bytes.size() - scan) / 2;
  damaged.insert(damaged.begin() + static_cast<long>(middle), {0xFF, 0xD9});
  auto marker = decodeJpegRgb(damaged.data(), damaged.size(), {64, 64});
  ASSERT_FALSE(marker.ok());
  EXPECT_EQ(marker.error().rfind("JPEG payload does not decode: damaged data (Corrupt JPEG data", 0), 0u)
      << marker.error();
}

TEST(JpegDecode, HarmlessWarningsAreCounted) {
  // Junk bytes before a marker (here the start of scan): libjpeg skips them with a warning, and the
  // pixels are those of the clean file.
  const auto bytes = encodeJpeg(texturedBgr(64, 48));
  const cv::Mat clean = decodeJpegRgb(bytes.data(), bytes.size(), {64, 48}).value();
  std::size_t scan = 0;
  for (std::size_t i = 0; i + 1 < bytes.size() && scan == 0; ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xDA) scan = i;
  ASSERT_GT(scan, 0u);
  std::vector<uint8_t> padded(bytes);
  padded.insert(padded.begin() + static_cast<long>(scan), {0x12, 0x34, 0x56});
  int warnings = 0;
  auto decoded = decodeJpegRgb(padded.data(), padded.size(), {64, 48}, &warnings);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(warnings, 1);
  EXPECT_EQ(cv::norm(decoded.value(), clean, cv::NORM_INF), 0.0);
}

TEST(JpegDecode, TooManyScansAreRefused) {
  // A progressive JPEG with one of its first AC scans (Ah = 0: it sets coefficients, so a copy
  // decodes as cleanly as the original) repeated: libjpeg only warns about the inconsistent
  // progression, and would decode every copy; the scan limit stops it.
  const auto bytes = encodeJpeg(texturedBgr(32, 32), true);
  auto markerAt = [&](std::size_t i) {  // a marker, not a stuffed 0xFF or a restart marker
    return bytes[i] == 0xFF && bytes[i + 1] != 0x00 && (bytes[i + 1] < 0xD0 || bytes[i + 1] > 0xD7);
  };
  std::size_t scan = 0, scan_end = 0;
  for (std::size_t i = 0; i + 1 < bytes.size() && scan == 0; ++i) {
    if (!(bytes[i] == 0xFF && bytes[i + 1] == 0xDA)) continue;
    // SOS: length (2), component count n, 2 n bytes of components, Ss, Se, Ah|Al.
    const std::size_t spectral = i + 4 + 1 + 2 * bytes[i + 4];
    if (bytes[spectral] > 0 && (bytes[spectral + 2] >> 4) == 0) scan = i;
  }
  ASSERT_GT(scan, 0u);
  for (std::size_t i = scan + 2; i + 1 < bytes.size() && scan_end == 0; ++i)
    if (markerAt(i)) scan_end = i;
  ASSERT_GT(scan_end, scan);
  std::vector<uint8_t> repeated(bytes.begin(), bytes.begin() + static_cast<long>(scan_end));
  for (int copy = 0; copy < kMaxJpegScans + 20; ++copy)
    repeated.insert(repeated.end(), bytes.begin() + static_cast<long>(scan),
                    bytes.begin() + static_cast<long>(scan_end));
  repeated.insert(repeated.end(), bytes.begin() + static_cast<long>(scan_end), bytes.end());
  auto decoded = decodeJpegRgb(repeated.data(), repeated.size(), {32, 32});
  ASSERT_FALSE(decoded.ok());
  EXPECT_EQ(decoded.error(), "JPEG payload does not decode: more than 100 scans");
  // The same file with its scans once decodes.
  EXPECT_TRUE(decodeJpegRgb(bytes.data(), bytes.size(), {32, 32}).ok());
}

}  // namespace
}  // namespace semfuse::wire
