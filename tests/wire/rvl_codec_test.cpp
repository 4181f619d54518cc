#include "semfuse/wire/rvl_codec.hpp"

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "shared_data.hpp"

namespace semfuse::wire {
namespace {

using Bytes = std::vector<uint8_t>;

Bytes rvlOf(const cv::Mat& units) {
  auto encoded = encodeRvl(units);
  EXPECT_TRUE(encoded.ok()) << encoded.error();
  return encoded.ok() ? encoded.value() : Bytes{};
}

std::string rvlError(const Bytes& bytes, cv::Size expected) {
  auto decoded = decodeRvl(bytes.data(), bytes.size(), expected);
  return decoded.ok() ? "<accepted>" : decoded.error();
}

// Encodes, decodes, and checks the image comes back bit for bit.
void expectRoundTrip(const cv::Mat& units) {
  const Bytes bytes = rvlOf(units);
  auto decoded = decodeRvl(bytes.data(), bytes.size(), units.size());
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  ASSERT_EQ(decoded.value().type(), CV_16UC1);
  EXPECT_EQ(cv::norm(decoded.value(), units, cv::NORM_INF), 0.0);
}

// The payload of an image of `size`: the header, then the stream's nibbles packed 8 to a
// little-endian word, the first in the top bits, as rvl_codec.hpp describes (written out by hand
// here, independently of the encoder).
Bytes payload(cv::Size size, const std::vector<uint8_t>& nibbles) {
  Bytes out;
  for (const uint32_t v : {static_cast<uint32_t>(size.width), static_cast<uint32_t>(size.height)}) {
    for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<uint8_t>(v >> shift));
  }
  for (std::size_t i = 0; i < nibbles.size(); i += 8) {
    uint32_t word = 0;
    for (std::size_t k = 0; k < 8; ++k) word = (word << 4) | (i + k < nibbles.size() ? nibbles[i + k] : 0u);
    for (int shift = 0; shift < 32; shift += 8) out.push_back(static_cast<uint8_t>(word >> shift));
  }
  return out;
}

cv::Mat row(std::initializer_list<uint16_t> values) {
  cv::Mat image(1, static_cast<int>(values.size()), CV_16UC1);
  int x = 0;
  for (const uint16_t v : values) image.at<uint16_t>(0, x++) = v;
  return image;
}

TEST(Rvl, BitLayoutIsThePapersNibbleStream) {
  // [0, 5, 3]: one zero (1), two non-zeros (2), 5 - 0 = 5 -> zigzag 10 = 0b001'010 -> nibbles
  // 0xA (010 and "more") then 0x1; 3 - 5 = -2 -> zigzag 3 -> 0x3. Word 0x12A13000.
  const cv::Mat image = row({0, 5, 3});
  const Bytes expected = {3, 0, 0, 0, 1, 0, 0, 0, 0x00, 0x30, 0xA1, 0x12};
  EXPECT_EQ(rvlOf(image), expected);
  EXPECT_EQ(payload(image.size(), {1, 2, 0xA, 1, 3}), expected);
  expectRoundTrip(image);

  // A 1x1 zero: one zero, no non-zero (the last pair ends at the image's end).
  EXPECT_EQ(rvlOf(cv::Mat(1, 1, CV_16UC1, cv::Scalar(0))), payload({1, 1}, {1, 0}));
  // A 1x1 65535: no zero, one non-zero of zigzag 131070 = 0b11'111'111'111'111'110, 6 nibbles.
  EXPECT_EQ(rvlOf(cv::Mat(1, 1, CV_16UC1, cv::Scalar(65535))), payload({1, 1}, {0, 1, 0xE, 0xF, 0xF, 0xF, 0xF, 3}));
}

TEST(Rvl, SyntheticEdgeCasesRoundTrip) {
  expectRoundTrip(cv::Mat(480, 640, CV_16UC1, cv::Scalar(0)));
  expectRoundTrip(cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000)));   // no zero
  expectRoundTrip(cv::Mat(480, 640, CV_16UC1, cv::Scalar(65535)));  // the largest value
  expectRoundTrip(cv::Mat(1, 1, CV_16UC1, cv::Scalar(0)));
  expectRoundTrip(cv::Mat(1, 1, CV_16UC1, cv::Scalar(1)));
  // The largest differences: 1 and 65535 alternating, with and without zeros between.
  cv::Mat extremes(7, 5, CV_16UC1);
  cv::Mat gaps(9, 1, CV_16UC1);
  for (int i = 0; i < 35; ++i) extremes.at<uint16_t>(i / 5, i % 5) = i % 2 ? 65535 : 1;
  for (int i = 0; i < 9; ++i) gaps.at<uint16_t>(i, 0) = i % 3 == 0 ? 0 : (i % 2 ? 65535 : 1);
  expectRoundTrip(extremes);
  expectRoundTrip(gaps);
  expectRoundTrip(gaps.t());
  // Odd sizes of random depth with random holes.
  std::mt19937 random(7);
  for (const cv::Size size : {cv::Size(3, 1), cv::Size(1, 3), cv::Size(13, 11), cv::Size(641, 479)}) {
    cv::Mat units(size, CV_16UC1);
    for (int y = 0; y < size.height; ++y) {
      for (int x = 0; x < size.width; ++x) {
        units.at<uint16_t>(y, x) = random() % 4 == 0 ? 0 : static_cast<uint16_t>(random() % 65536);
      }
    }
    SCOPED_TRACE(std::to_string(size.width) + "x" + std::to_string(size.height));
    expectRoundTrip(units);
  }
  // A region of a larger image (rows not contiguous) encodes as its copy.
  const cv::Mat region = extremes(cv::Rect(1, 2, 3, 4));
  EXPECT_EQ(rvlOf(region), rvlOf(region.clone()));
}

TEST(Rvl, SizesOfUniformImages) {
  // All zero: one count of 307200 (7 nibbles) and a 0 fill one word; a constant image costs its
  // first value (1000 -> zigzag 2000, 4 nibbles) and a nibble per pixel after it.
  EXPECT_EQ(rvlOf(cv::Mat(480, 640, CV_16UC1, cv::Scalar(0))).size(), kRvlHeaderBytes + 4);
  EXPECT_EQ(rvlOf(cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000))).size(),
            kRvlHeaderBytes + (1 + 7 + 4 + (640 * 480 - 1) + 7) / 8 * 4);
}

// Real depth comes back bit for bit, in a fraction of the raw size.
void expectRealFramesRoundTrip(const std::vector<std::filesystem::path>& files, double max_fraction_of_raw) {
  for (const auto& file : files) {
    SCOPED_TRACE(file.string());
    const cv::Mat units = cv::imread(file.string(), cv::IMREAD_ANYDEPTH);
    ASSERT_EQ(units.type(), CV_16UC1);
    ASSERT_EQ(units.size(), cv::Size(640, 480));
    expectRoundTrip(units);
    const double raw = static_cast<double>(units.total() * 2);
    EXPECT_LT(static_cast<double>(rvlOf(units).size()), max_fraction_of_raw * raw);
  }
}

TEST(Rvl, SevenScenesDepthRoundTrips) {
  const auto dir = semfuse::testing::redkitchenDir();
  SEMFUSE_REQUIRE_SHARED_DIR(dir);
  expectRealFramesRoundTrip(
      {dir / "frame-000000.depth.png", dir / "frame-000250.depth.png", dir / "frame-000499.depth.png"}, 0.5);
}

TEST(Rvl, TumDepthRoundTrips) {
  const auto dir = semfuse::testing::sharedDir() / "data" / "rgbd_dataset_freiburg1_xyz" / "depth";
  SEMFUSE_REQUIRE_SHARED_DIR(dir);
  // TUM depth is in units of 0.2 mm: larger differences between neighbours than 7-Scenes' mm.
  expectRealFramesRoundTrip({dir / "1305031102.160407.png", dir / "1305031128.754646.png"}, 0.6);
}

TEST(Rvl, EncoderRefusesWhatIsNotA16BitImage) {
  EXPECT_EQ(encodeRvl(cv::Mat(2, 2, CV_32FC1, cv::Scalar(1.0f))).error(), "RVL encodes CV_16UC1 images only");
  EXPECT_EQ(encodeRvl(cv::Mat()).error(), "RVL encodes CV_16UC1 images only");
  EXPECT_EQ(encodeRvl(cv::Mat(0, 4, CV_16UC1)).error(), "RVL: empty image");
}

TEST(RvlBadInput, HeaderAndSize) {
  const Bytes good = rvlOf(row({0, 5, 3}));
  EXPECT_EQ(rvlError(Bytes(good.begin(), good.begin() + 7), {3, 1}),
            "RVL payload of 7 bytes is shorter than its 8-byte size header");
  EXPECT_EQ(rvlError(good, {1, 3}), "RVL payload declares 3x1, expected 1x3");
  EXPECT_EQ(rvlError(payload({0, 1}, {}), {0, 1}), "RVL payload declares an empty image");
  Bytes huge = good;
  huge[3] = 0x80;  // width 2^31 + 3
  EXPECT_EQ(rvlDeclaredSize(huge.data(), huge.size()).error(), "RVL payload declares 2147483651x1 pixels");
  EXPECT_EQ(rvlDeclaredSize(nullptr, 0).error(), "RVL payload of 0 bytes is shorter than its 8-byte size header");
}

TEST(RvlBadInput, TruncatedOverlongAndPaddedStreams) {
  const Bytes good = rvlOf(row({0, 5, 3}));
  ASSERT_EQ(rvlError(good, {3, 1}), "<accepted>");
  EXPECT_EQ(rvlError(Bytes(good.begin(), good.end() - 1), {3, 1}),
            "RVL payload's stream of 3 bytes is not whole 32-bit words");
  EXPECT_EQ(rvlError(Bytes(good.begin(), good.begin() + 8), {3, 1}), "RVL payload ends at pixel 0 of 3 (truncated)");
  Bytes overlong = good;
  overlong.insert(overlong.end(), 4, 0);
  EXPECT_EQ(rvlError(overlong, {3, 1}), "RVL payload has 4 bytes after the last pixel");
  EXPECT_EQ(rvlError(payload({3, 1}, {1, 2, 0xA, 1, 3, 0, 0, 7}), {3, 1}),
            "RVL payload has non-zero padding after the last pixel");
  // A stream cut at a word boundary inside the image: the first word of a 16-pixel ramp holds
  // the two counts (1 + 2 nibbles), 1000 (4) and the first nibble of the next difference, 10.
  cv::Mat ramp(1, 16, CV_16UC1);
  for (int x = 0; x < 16; ++x) ramp.at<uint16_t>(0, x) = static_cast<uint16_t>(1000 + 10 * x);
  const Bytes long_run = rvlOf(ramp);
  EXPECT_EQ(rvlError(Bytes(long_run.begin(), long_run.begin() + 12), {16, 1}),
            "RVL payload ends at pixel 1 of 16 (truncated)");
}

TEST(RvlBadInput, RunsThatDoNotFitTheImage) {
  EXPECT_EQ(rvlError(payload({2, 1}, {3, 0}), {2, 1}),
            "RVL payload has a run of 3 zero pixels at pixel 0 that overflows the 2-pixel image");
  EXPECT_EQ(rvlError(payload({2, 1}, {1, 2, 2, 0}), {2, 1}),
            "RVL payload has a run of 2 non-zero pixels at pixel 1 that overflows the 2-pixel image");
  // A run count near 2^32 must not wrap the pixel arithmetic.
  EXPECT_EQ(rvlError(payload({2, 1}, {0xF, 0xF, 0xF, 0xF, 0xF, 0xF, 0xF, 0xF, 0xF, 0xF, 3}), {2, 1}),
            "RVL payload has a run of 4294967295 zero pixels at pixel 0 that overflows the 2-pixel image");
  // (1 zero, 1 non-zero), then a pair without zeros, which the encoder never writes.
  EXPECT_EQ(rvlError(payload({3, 1}, {1, 1, 2, 0, 1, 2}), {3, 1}), "RVL payload has an empty run of zeros at pixel 2");
  // A pair with no non-zero pixel before the image's end.
  EXPECT_EQ(rvlError(payload({3, 1}, {1, 0, 1, 1, 2}), {3, 1}),
            "RVL payload has an empty run of non-zero pixels at pixel 1");
  EXPECT_EQ(rvlError(payload({3, 1}, {0, 0}), {3, 1}), "RVL payload has an empty run of non-zero pixels at pixel 0");
}

TEST(RvlBadInput, NumbersAndValuesThatAreNotCanonical) {
  // The count 1 written as 0x9 0x0: a superfluous zero nibble.
  EXPECT_EQ(rvlError(payload({1, 1}, {9, 0, 0}), {1, 1}),
            "RVL payload has a count or value with a superfluous zero nibble at pixel 0");
  // Twelve nibbles with "more" set: longer than any count or value.
  EXPECT_EQ(rvlError(payload({1, 1}, std::vector<uint8_t>(12, 0xF)), {1, 1}),
            "RVL payload has a count or value longer than 32 bits at pixel 0");
  // Eleven nibbles of value bits: 2^33 - 1.
  std::vector<uint8_t> too_big(10, 0xF);
  too_big.push_back(7);
  EXPECT_EQ(rvlError(payload({1, 1}, too_big), {1, 1}),
            "RVL payload has a count or value longer than 32 bits at pixel 0");
  // First value zigzag 1: a difference of -1 from 0.
  EXPECT_EQ(rvlError(payload({1, 1}, {0, 1, 1}), {1, 1}),
            "RVL payload decodes pixel 0 of a non-zero run to -1, outside 1..65535");
  // 5 then 5 - 5 = 0 inside a non-zero run (zigzag 9 = 0x9 0x1).
  EXPECT_EQ(rvlError(payload({2, 1}, {0, 2, 0xA, 1, 9, 1}), {2, 1}),
            "RVL payload decodes pixel 1 of a non-zero run to 0, outside 1..65535");
  // Zigzag 131072: beyond the difference of any two 16-bit values (0x8 0x8 0x8 0x8 0x8 0x4).
  EXPECT_EQ(rvlError(payload({1, 1}, {0, 1, 8, 8, 8, 8, 8, 4}), {1, 1}),
            "RVL payload has a difference of 131072 (zigzag) at pixel 0, beyond any two 16-bit values");
  // 65535 + 1.
  EXPECT_EQ(rvlError(payload({2, 1}, {0, 2, 0xE, 0xF, 0xF, 0xF, 0xF, 3, 2}), {2, 1}),
            "RVL payload decodes pixel 1 of a non-zero run to 65536, outside 1..65535");
}

TEST(RvlBadInput, GarbageNeverCrashesAndWhatDecodesIsWhatItEncodes) {
  // Random nibbles behind a valid header, and valid streams of random small images with a few
  // nibbles changed: each either fails with a message or is exactly the encoding of the image it
  // decodes to (the decoder accepts canonical streams only).
  std::mt19937 random(11);
  int accepted = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const cv::Size size(1 + static_cast<int>(random() % 5), 1 + static_cast<int>(random() % 3));
    std::vector<uint8_t> nibbles;
    if (trial % 2 == 0) {
      nibbles.resize(1 + random() % 24);
      for (auto& nibble : nibbles) nibble = static_cast<uint8_t>(random() % 16);
    } else {
      cv::Mat units(size, CV_16UC1);
      for (int i = 0; i < size.area(); ++i) {
        units.at<uint16_t>(i / size.width, i % size.width) =
            random() % 3 == 0 ? 0 : static_cast<uint16_t>(1 + random() % (random() % 2 ? 40 : 65535));
      }
      const Bytes valid = rvlOf(units);
      for (std::size_t i = kRvlHeaderBytes; i < valid.size(); i += 4) {
        const uint32_t word = uint32_t{valid[i]} | (uint32_t{valid[i + 1]} << 8) | (uint32_t{valid[i + 2]} << 16) |
                              (uint32_t{valid[i + 3]} << 24);
        for (int k = 7; k >= 0; --k) nibbles.push_back(static_cast<uint8_t>((word >> (4 * k)) & 0xF));
      }
      for (int change = 1 + static_cast<int>(random() % 3); change > 0; --change) {
        nibbles[random() % nibbles.size()] = static_cast<uint8_t>(random() % 16);
      }
    }
    const Bytes bytes = payload(size, nibbles);
    auto decoded = decodeRvl(bytes.data(), bytes.size(), size);
    if (!decoded) {
      EXPECT_EQ(decoded.error().rfind("RVL payload ", 0), 0u) << decoded.error();
      continue;
    }
    ++accepted;
    EXPECT_EQ(rvlOf(decoded.value()), bytes);
  }
  EXPECT_GT(accepted, 1000);  // changed values are often other valid images: the check is exercised
}

TEST(RvlBadInput, EveryCutAndEveryFlippedBitOfARealPatchIsCaughtOrCanonical) {
  const auto dir = semfuse::testing::redkitchenDir();
  SEMFUSE_REQUIRE_SHARED_DIR(dir);
  const cv::Mat units = cv::imread((dir / "frame-000000.depth.png").string(), cv::IMREAD_ANYDEPTH);
  ASSERT_FALSE(units.empty());
  const cv::Mat patch = units(cv::Rect(300, 200, 24, 16)).clone();
  const Bytes good = rvlOf(patch);
  for (std::size_t length = 0; length < good.size(); ++length) {
    EXPECT_NE(rvlError(Bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length)), patch.size()),
              "<accepted>")
        << "cut at " << length;
  }
  for (std::size_t bit = kRvlHeaderBytes * 8; bit < good.size() * 8; ++bit) {
    Bytes flipped = good;
    flipped[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    auto decoded = decodeRvl(flipped.data(), flipped.size(), patch.size());
    if (decoded) {
      EXPECT_EQ(rvlOf(decoded.value()), flipped) << "bit " << bit;
    }
  }
}

}  // namespace
}  // namespace semfuse::wire
