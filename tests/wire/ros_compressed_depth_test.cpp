// ROS 2 compressed depth (compressed_depth_image_transport's format), PNG and RVL.
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/wire/image_convert.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/rvl_codec.hpp"
#include "shared_data.hpp"

namespace semfuse::wire {
namespace {

using Bytes = std::vector<uint8_t>;

// A message over `format` and `data` (not owned: the caller keeps both alive).
sensor_msgs_msg_dds__CompressedImage_ compressedDepth(const std::string& format, Bytes& data) {
  sensor_msgs_msg_dds__CompressedImage_ msg{};
  msg.format = const_cast<char*>(format.c_str());
  msg.data = {static_cast<uint32_t>(data.size()), static_cast<uint32_t>(data.size()), data.data(), false};
  return msg;
}

void appendUint32(Bytes& out, uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<uint8_t>(value >> shift));
}
void appendFloat(Bytes& out, float value) {
  uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  appendUint32(out, bits);
}

// The 12-byte configuration header, then `payload`.
Bytes withConfigHeader(const Bytes& payload, float a = 0.0f, float b = 0.0f, uint32_t kind = 0) {
  Bytes data;
  appendUint32(data, kind);
  appendFloat(data, a);
  appendFloat(data, b);
  data.insert(data.end(), payload.begin(), payload.end());
  return data;
}

Bytes rvlPayload(const cv::Mat& units) { return encodeRvl(units).value(); }
Bytes pngOf(const cv::Mat& units) {
  Bytes png;
  EXPECT_TRUE(cv::imencode(".png", units, png));
  return png;
}

cv::Mat millimetres() {
  cv::Mat mm(48, 64, CV_16UC1);
  for (int y = 0; y < mm.rows; ++y) {
    for (int x = 0; x < mm.cols; ++x)
      mm.at<uint16_t>(y, x) = (x * y) % 7 == 3 ? 0 : static_cast<uint16_t>(800 + x + 3 * y);
  }
  return mm;
}

std::string decodeError(const std::string& format, Bytes data) {
  auto metres = compressedDepthToMetres(compressedDepth(format, data));
  return metres.ok() ? "<accepted>" : metres.error();
}

TEST(RosCompressedDepth, TheBytesAreTheTransportsLayout) {
  // [0, 5, 3] mm, written out by hand: header (format 0, a = b = 0), width 3, height 1, then the
  // RVL word 0x12A13000 (rvl_codec_test has its nibbles).
  const cv::Mat mm = (cv::Mat_<uint16_t>(1, 3) << 0, 5, 3);
  const Bytes expected = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 1, 0, 0, 0, 0x00, 0x30, 0xA1, 0x12};
  auto owned = compressedDepthFromMillimetres(mm, "rvl", {4, 5}, "depth_optical");
  ASSERT_TRUE(owned.ok()) << owned.error();
  const auto& msg = owned.value().msg();
  EXPECT_STREQ(msg.format, "16UC1; compressedDepth rvl");
  EXPECT_STREQ(msg.header.frame_id, "depth_optical");
  EXPECT_EQ(Bytes(msg.data._buffer, msg.data._buffer + msg.data._length), expected);

  Bytes data = expected;
  for (const std::string format :
       {"16UC1; compressedDepth rvl", "mono16; compressedDepth rvl", "16uc1;compresseddepth RVL"}) {
    auto metres = compressedDepthToMetres(compressedDepth(format, data));
    ASSERT_TRUE(metres.ok()) << format << ": " << metres.error();
    ASSERT_EQ(metres.value().type(), CV_32FC1);
    EXPECT_EQ(metres.value().at<float>(0, 0), 0.0f);
    EXPECT_FLOAT_EQ(metres.value().at<float>(0, 1), 0.005f);
    EXPECT_FLOAT_EQ(metres.value().at<float>(0, 2), 0.003f);
  }
}

TEST(RosCompressedDepth, RvlAndPngOfMillimetresGiveTheSameMetres) {
  const cv::Mat mm = millimetres();
  const cv::Mat expected = depthUnitsToMetres(mm, 0.001);
  Bytes rvl = withConfigHeader(rvlPayload(mm));
  Bytes png = withConfigHeader(pngOf(mm));
  Bytes plain_png = pngOf(mm);
  const std::pair<std::string, Bytes*> cases[] = {{"16UC1; compressedDepth rvl", &rvl},
                                                  {"16UC1; compressedDepth png", &png},
                                                  {"16UC1; compressedDepth", &png},  // older transports: PNG
                                                  {"16UC1; png compressed", &plain_png}};
  for (const auto& [format, data] : cases) {
    auto metres = compressedDepthToMetres(compressedDepth(format, *data));
    ASSERT_TRUE(metres.ok()) << format << ": " << metres.error();
    EXPECT_EQ(cv::norm(metres.value(), expected, cv::NORM_INF), 0.0) << format;
  }
  EXPECT_LT(rvl.size(), png.size());  // RVL is the smaller of the two here
}

TEST(RosCompressedDepth, SevenScenesFrameThroughBothCompressions) {
  const auto dir = semfuse::testing::redkitchenDir();
  SEMFUSE_REQUIRE_SHARED_DIR(dir);
  const cv::Mat mm = cv::imread((dir / "frame-000100.depth.png").string(), cv::IMREAD_ANYDEPTH);
  ASSERT_EQ(mm.type(), CV_16UC1);
  for (const std::string compression : {"rvl", "png"}) {
    auto owned = compressedDepthFromMillimetres(mm, compression, {}, "cam");
    ASSERT_TRUE(owned.ok()) << owned.error();
    auto metres = compressedDepthToMetres(owned.value().msg());
    ASSERT_TRUE(metres.ok()) << compression << ": " << metres.error();
    EXPECT_EQ(cv::norm(metres.value(), depthUnitsToMetres(mm, 0.001), cv::NORM_INF), 0.0) << compression;
  }
}

TEST(RosCompressedDepth, Float32IsTheQuantisedInverseDepth) {
  // The transport's defaults (depth_max 10 m, quantisation 100): a = 100 * 101 = 10100,
  // b = 1 - a / 10 = -1009; 1 m is stored as a / 1 + b = 9091, 2 m as 4041.
  const cv::Mat quantised = (cv::Mat_<uint16_t>(1, 3) << 0, 9091, 4041);
  for (const std::string compression : {"rvl", "png"}) {
    Bytes data = withConfigHeader(compression == "rvl" ? rvlPayload(quantised) : pngOf(quantised), 10100.0f, -1009.0f);
    auto metres = compressedDepthToMetres(compressedDepth("32FC1; compressedDepth " + compression, data));
    ASSERT_TRUE(metres.ok()) << compression << ": " << metres.error();
    EXPECT_EQ(metres.value().at<float>(0, 0), 0.0f);  // no depth
    EXPECT_FLOAT_EQ(metres.value().at<float>(0, 1), 1.0f);
    EXPECT_FLOAT_EQ(metres.value().at<float>(0, 2), 2.0f);
  }
  Bytes bad_a = withConfigHeader(rvlPayload(quantised), 0.0f, -1009.0f);
  EXPECT_EQ(decodeError("32FC1; compressedDepth rvl", bad_a),
            "compressed depth: inverse depth parameters a 0.000000, b -1009.000000 (a must be finite and > 0, b "
            "finite)");
  Bytes behind = withConfigHeader(rvlPayload(quantised), 10100.0f, 5000.0f);  // 9091 is fine, 4041 < b
  EXPECT_EQ(decodeError("32FC1; compressedDepth rvl", behind),
            "compressed depth: value 4041 at (2, 0) decodes to depth -10.531804 with a 10100.000000, b 5000.000000");
}

TEST(RosCompressedDepth, BadFormatsAndHeadersAreRefused) {
  const cv::Mat mm = millimetres();
  Bytes rvl = withConfigHeader(rvlPayload(mm));
  EXPECT_EQ(decodeError("16UC1; compressedDepth zstd", rvl),
            "compressed depth: unknown compression 'zstd' in format '16UC1; compressedDepth zstd' (known: png, rvl)");
  EXPECT_EQ(decodeError("rgb8; compressedDepth rvl", rvl),
            "compressed depth: format 'rgb8; compressedDepth rvl' is not of a depth encoding (16UC1, mono16, 32FC1)");
  EXPECT_EQ(decodeError("16UC1; jpeg compressed", rvl),
            "compressed depth: unknown format '16UC1; jpeg compressed' (known: compressedDepth png or rvl, or a 16-bit "
            "png)");
  EXPECT_EQ(decodeError("32FC1; png compressed", rvl),
            "compressed depth: unknown format '32FC1; png compressed' (known: compressedDepth png or rvl, or a 16-bit "
            "png)");
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", Bytes(12, 0)),
            "compressed depth: 12 bytes, no payload after the 12-byte configuration header");
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", withConfigHeader(rvlPayload(mm), 0.0f, 0.0f, 1)),
            "compressed depth: configuration header says compression format 1 (known: 0, inverse depth)");
  // PNG where RVL is said, and the other way round.
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", withConfigHeader(pngOf(mm))),
            "compressed depth: image size 1196314761x169478669 exceeds the 8192-pixel limit");  // "\x89PNG\r\n\x1a\n"
  EXPECT_EQ(decodeError("16UC1; compressedDepth png", rvl),
            "compressed depth: PNG payload does not decode: not a PNG (bad signature or header)");
  // An 8-bit PNG is not depth.
  EXPECT_EQ(decodeError("16UC1; compressedDepth png", withConfigHeader(pngOf(cv::Mat(4, 4, CV_8UC1, cv::Scalar(1))))),
            "compressed depth: PNG decodes to 4x4 8UC1, declared 4x4 16UC1");

  const std::string format = "16UC1; compressedDepth rvl";
  sensor_msgs_msg_dds__CompressedImage_ cut = compressedDepth(format, rvl);
  cut.data._length = cut.data._maximum + 1;
  EXPECT_EQ(compressedDepthToMetres(cut).error(), "compressed depth: truncated sequence, length " +
                                                      std::to_string(rvl.size() + 1) + " exceeds its allocation of " +
                                                      std::to_string(rvl.size()));
}

TEST(RosCompressedDepth, BadRvlPayloadsAreRefusedBeforeAnythingIsAllocated) {
  const cv::Mat mm = millimetres();
  Bytes huge = withConfigHeader(rvlPayload(mm));
  huge[12] = 0x28;  // width 9000 (0x2328)
  huge[13] = 0x23;
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", huge),
            "compressed depth: image size 9000x48 exceeds the 8192-pixel limit");
  Bytes cut = withConfigHeader(rvlPayload(mm));
  cut.resize(cut.size() - 8);
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", cut).rfind("compressed depth: RVL payload ends at pixel ", 0),
            0u);
  Bytes padded = withConfigHeader(rvlPayload(mm));
  padded.insert(padded.end(), 4, 0);
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", padded),
            "compressed depth: RVL payload has 4 bytes after the last pixel");
  EXPECT_EQ(decodeError("16UC1; compressedDepth rvl", withConfigHeader(Bytes{1, 2, 3})),
            "compressed depth: RVL payload of 3 bytes is shorter than its 8-byte size header");
}

TEST(RosCompressedDepth, TheColourDecoderAndTheEncoderRefuseWhatIsNotTheirs) {
  const cv::Mat mm = millimetres();
  Bytes rvl = withConfigHeader(rvlPayload(mm));
  EXPECT_EQ(compressedImageToMat(compressedDepth("16UC1; compressedDepth rvl", rvl)).error(),
            "compressed image: format '16uc1; compresseddepth rvl' is compressedDepth, which only the compressed depth "
            "input reads");
  EXPECT_EQ(compressedDepthFromMillimetres(cv::Mat(2, 2, CV_32FC1), "rvl", {}, "").error(),
            "compressed depth: millimetres must be CV_16UC1, got 32FC1");
  EXPECT_EQ(compressedDepthFromMillimetres(mm, "zstd", {}, "").error(),
            "compressed depth: unknown compression 'zstd' (known: png, rvl)");
}

}  // namespace
}  // namespace semfuse::wire
