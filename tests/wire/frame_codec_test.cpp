#include "semfuse/wire/frame_codec.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/wire/rvl_codec.hpp"
#include "test_frames.hpp"

namespace semfuse::wire {
namespace {

using testing::makeFrame;

double maxDifference(const cv::Mat& a, const cv::Mat& b) { return cv::norm(a, b, cv::NORM_INF); }

void expectSameMetadata(const Frame& in, const Frame& out) {
  EXPECT_EQ(out.camera_id, in.camera_id);
  EXPECT_EQ(out.seq, in.seq);
  EXPECT_EQ(out.stamp.sec, in.stamp.sec);
  EXPECT_EQ(out.stamp.nanosec, in.stamp.nanosec);
  EXPECT_EQ(out.frame_id, in.frame_id);
  EXPECT_EQ(out.intrinsics.width, in.intrinsics.width);
  EXPECT_DOUBLE_EQ(out.intrinsics.fy, in.intrinsics.fy);
  EXPECT_DOUBLE_EQ(out.intrinsics.cx, in.intrinsics.cx);
  ASSERT_TRUE(out.camera_to_world.has_value());
  EXPECT_EQ(out.camera_to_world->matrix(), in.camera_to_world->matrix());  // doubles travel exactly
}

struct Case {
  std::string depth;
  std::string color;
};

class FrameRoundTrip : public ::testing::TestWithParam<Case> {};

TEST_P(FrameRoundTrip, DecodesWhatWasEncoded) {
  const Frame in = makeFrame();
  FrameEncoding encoding;
  encoding.depth = GetParam().depth;
  encoding.color = GetParam().color;
  auto encoded = encodeFrame(in, encoding);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  EXPECT_EQ(std::string(encoded.value().msg().depth_encoding), encoding.depth);
  EXPECT_FALSE(encoded.value().msg().depth._release);

  auto out = decodeFrame(encoded.value().msg());
  ASSERT_TRUE(out.ok()) << out.error();
  expectSameMetadata(in, out.value());
  ASSERT_EQ(out.value().depth.type(), CV_32FC1);
  // Whole millimetres: every depth encoding is exact up to float rounding of the scale.
  EXPECT_LT(maxDifference(in.depth, out.value().depth), 1e-6);
  EXPECT_EQ(cv::countNonZero(out.value().depth == 0.0f), cv::countNonZero(in.depth == 0.0f));
  if (encoding.color.empty()) {
    EXPECT_TRUE(out.value().color.empty());
  } else if (encoding.color == "jpeg") {
    ASSERT_EQ(out.value().color.type(), CV_8UC3);
    EXPECT_LT(cv::norm(in.color, out.value().color, cv::NORM_L1) / static_cast<double>(in.color.total() * 3), 3.0);
  } else {
    EXPECT_EQ(maxDifference(in.color, out.value().color), 0.0);  // raw and PNG are lossless
  }
}

INSTANTIATE_TEST_SUITE_P(AllEncodings, FrameRoundTrip,
                         ::testing::Values(Case{"16UC1", "rgb8"}, Case{"32FC1", "bgr8"}, Case{"png16", "png"},
                                           Case{"16UC1", "jpeg"}, Case{"png16", ""}, Case{"32FC1", "jpeg"},
                                           Case{"rvl", "jpeg"}, Case{"rvl", ""}),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return info.param.depth + "_" + (info.param.color.empty() ? "none" : info.param.color);
                         });

TEST(FrameCodec, EncodesThe16BitFormatInMillimetresWithTheScale) {
  Frame in = makeFrame(4, 2, false);
  in.depth.at<float>(0, 1) = 1.234f;
  in.depth.at<float>(0, 2) = std::nanf("");
  in.depth.at<float>(0, 3) = 70.0f;  // beyond 65.535 m: not representable, sent invalid
  auto encoded = encodeFrame(in);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  const auto& msg = encoded.value().msg();
  EXPECT_FLOAT_EQ(msg.depth_scale, 0.001f);
  ASSERT_EQ(msg.depth._length, 4u * 2u * 2u);
  const auto* units = reinterpret_cast<const uint16_t*>(msg.depth._buffer);
  EXPECT_EQ(units[1], 1234);
  EXPECT_EQ(units[2], 0);
  EXPECT_EQ(units[3], 0);
  EXPECT_STREQ(msg.color_encoding, "");  // no colour in the frame
  EXPECT_EQ(msg.color._length, 0u);
}

TEST(FrameCodec, EncodedFrameStaysValidWhenMoved) {
  auto encoded = encodeFrame(makeFrame());
  ASSERT_TRUE(encoded.ok());
  EncodedFrame moved = std::move(encoded).value();
  std::vector<EncodedFrame> frames;
  frames.push_back(std::move(moved));
  auto out = decodeFrame(frames.front().msg());
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().camera_id, "cam0");
}

TEST(FrameCodec, FrameWithoutPoseDecodesWithout) {
  Frame in = makeFrame();
  in.camera_to_world.reset();
  auto encoded = encodeFrame(in);
  ASSERT_TRUE(encoded.ok());
  EXPECT_FALSE(encoded.value().msg().has_pose);
  auto out = decodeFrame(encoded.value().msg());
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_FALSE(out.value().camera_to_world.has_value());
}

TEST(FrameCodec, EncoderRejectsWrongImageTypesAndEncodings) {
  Frame in = makeFrame();
  FrameEncoding encoding;
  encoding.depth = "16UC2";
  auto bad_encoding = encodeFrame(in, encoding);
  ASSERT_FALSE(bad_encoding.ok());
  EXPECT_EQ(bad_encoding.error(), "depth: unknown encoding '16UC2' (known: 16UC1, 32FC1, png16, rvl)");
  in.depth.convertTo(in.depth, CV_64F);
  auto bad_type = encodeFrame(in);
  ASSERT_FALSE(bad_type.ok());
  EXPECT_EQ(bad_type.error(), "encodeFrame: depth must be CV_32FC1 metres, got 64FC1");
}

// Each malformed message is rejected with its own message.
class BadFrame : public ::testing::Test {
 protected:
  void SetUp() override {
    auto encoded = encodeFrame(makeFrame(640, 480), FrameEncoding{});
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    encoded_ = std::make_unique<EncodedFrame>(std::move(encoded).value());
  }
  semfuse_msg_dds__Frame_& msg() { return encoded_->msg(); }
  std::string decodeError() {
    auto result = decodeFrame(msg());
    return result.ok() ? "<accepted>" : result.error();
  }
  std::unique_ptr<EncodedFrame> encoded_;
};

TEST_F(BadFrame, DepthDataSizeDisagreesWithDimensions) {
  msg().depth._length -= 2;
  EXPECT_EQ(decodeError(), "depth: 614398 bytes for 640x480 16UC1, expected 614400");
}

TEST_F(BadFrame, TruncatedSequence) {
  msg().depth._length = msg().depth._maximum + 10;
  EXPECT_EQ(decodeError(), "depth: truncated sequence, length 614410 exceeds its allocation of 614400");
  msg().depth._length = 614400;
  msg().depth._buffer = nullptr;
  EXPECT_EQ(decodeError(), "depth: truncated sequence, length 614400 but no data");
}

TEST_F(BadFrame, ColorDataSize) {
  msg().color._length = 1000;
  EXPECT_EQ(decodeError(), "color: 1000 bytes for 640x480 rgb8, expected 921600");
}

TEST_F(BadFrame, ZeroNegativeAndNonFiniteIntrinsics) {
  msg().intrinsics.fx = 0.0;
  EXPECT_EQ(decodeError(), "intrinsics: focal lengths must be finite and > 0, got fx=0 fy=51");
  msg().intrinsics.fx = 50.0;
  msg().intrinsics.fy = -3.0;
  EXPECT_EQ(decodeError(), "intrinsics: focal lengths must be finite and > 0, got fx=50 fy=-3");
  msg().intrinsics.fy = 51.0;
  msg().intrinsics.cx = std::nan("");
  EXPECT_EQ(decodeError(), "intrinsics: principal point must be finite, got cx=nan cy=239.5");
}

TEST_F(BadFrame, ZeroOrHugeImageSize) {
  msg().intrinsics.width = 0;
  EXPECT_EQ(decodeError(), "frame: image size 0x480 is empty");
  msg().intrinsics.width = 100000;
  EXPECT_EQ(decodeError(), "frame: image size 100000x480 exceeds the 8192-pixel limit");
}

TEST_F(BadFrame, NonFinitePose) {
  msg().camera_to_world[6] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(decodeError(), "pose: non-finite value nan at row 1, column 2");
}

TEST_F(BadFrame, NonOrthonormalPoseReportsTheError) {
  msg().camera_to_world[0] *= 1.5;
  const std::string error = decodeError();
  // R's first column scaled by 1.5: |R^T R - I| is measured and reported (1.1646 here).
  EXPECT_EQ(error, "pose: rotation is not orthonormal (|R^T R - I| = 1.1646, tolerance 0.001)");
}

TEST_F(BadFrame, UnknownEncodingsListTheKnownOnes) {
  msg().depth_encoding = const_cast<char*>("mono16");
  EXPECT_EQ(decodeError(), "depth: unknown encoding 'mono16' (known: 16UC1, 32FC1, png16, rvl)");
  msg().depth_encoding = const_cast<char*>("16UC1");
  msg().color_encoding = const_cast<char*>("yuv422");
  EXPECT_EQ(decodeError(), "color: unknown encoding 'yuv422' (known: \"\", rgb8, bgr8, jpeg, png)");
}

TEST_F(BadFrame, BadDepthScale) {
  msg().depth_scale = 0.0f;
  EXPECT_EQ(decodeError(), "depth: depth_scale must be finite and > 0 for 16UC1, got 0.000000");
}

TEST_F(BadFrame, EmptyCameraId) {
  msg().camera_id = const_cast<char*>("");
  EXPECT_EQ(decodeError(), "frame: empty camera_id");
}

TEST(FrameCodecPayloads, PngThatDoesNotDecodeOrHasOtherSize) {
  FrameEncoding encoding;
  encoding.depth = "png16";
  encoding.color = "png";
  auto encoded = encodeFrame(makeFrame(), encoding);
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  std::vector<uint8_t> garbage(100, 0x42);
  const auto saved_depth = msg.depth;
  msg.depth._buffer = garbage.data();
  msg.depth._length = msg.depth._maximum = 100;
  auto not_png = decodeFrame(msg);
  ASSERT_FALSE(not_png.ok());
  EXPECT_EQ(not_png.error(), "depth: PNG payload does not decode: not a PNG (bad signature or header)");

  msg.depth = saved_depth;
  msg.intrinsics.width = 32;  // the PNGs hold 64x48
  auto other_size = decodeFrame(msg);
  ASSERT_FALSE(other_size.ok());
  EXPECT_EQ(other_size.error(), "depth: PNG declares 64x48, frame declares 32x48");

  // An 8-bit PNG of the right size where 16-bit depth is declared.
  msg.intrinsics.width = 64;
  std::vector<uint8_t> png8;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(48, 64, CV_8UC1, cv::Scalar(9)), png8));
  msg.depth._buffer = png8.data();
  msg.depth._length = msg.depth._maximum = static_cast<uint32_t>(png8.size());
  auto wrong_depth = decodeFrame(msg);
  ASSERT_FALSE(wrong_depth.ok());
  EXPECT_EQ(wrong_depth.error(), "depth: PNG decodes to 64x48 8UC1, declared 64x48 16UC1");
}

TEST(FrameCodec, RvlCarriesTheUnitsWithTheScale) {
  // 0.25 mm units: the payload is the RVL image of the units, decoded with the frame's scale.
  Frame in = makeFrame(5, 3, false);
  in.depth.at<float>(1, 2) = 0.00025f * 4001;
  FrameEncoding encoding;
  encoding.depth = "rvl";
  encoding.depth_scale = 0.00025;
  auto encoded = encodeFrame(in, encoding);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  const auto& msg = encoded.value().msg();
  EXPECT_FLOAT_EQ(msg.depth_scale, 0.00025f);
  auto units = decodeRvl(msg.depth._buffer, msg.depth._length, cv::Size(5, 3));
  ASSERT_TRUE(units.ok()) << units.error();
  EXPECT_EQ(units.value().at<uint16_t>(1, 2), 4001);
  EXPECT_EQ(units.value().at<uint16_t>(0, 0), 0);     // (x + y) % 11 == 0: no depth
  EXPECT_EQ(units.value().at<uint16_t>(0, 1), 2028);  // 507 mm
  auto out = decodeFrame(msg);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_NEAR(out.value().depth.at<float>(1, 2), 1.00025f, 1e-6f);
  EXPECT_EQ(out.value().depth.at<float>(0, 0), 0.0f);
}

TEST(FrameCodecPayloads, RvlOfAnotherSizeOrDamagedIsRefused) {
  FrameEncoding encoding;
  encoding.depth = "rvl";
  auto encoded = encodeFrame(makeFrame(), encoding);
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  const auto saved = msg.depth;
  msg.intrinsics.width = 32;  // the payload holds 64x48
  EXPECT_EQ(decodeFrame(msg).error(), "depth: RVL declares 64x48, frame declares 32x48");
  msg.intrinsics.width = 64;
  msg.depth._length = 5;
  EXPECT_EQ(decodeFrame(msg).error(), "depth: RVL payload of 5 bytes is shorter than its 8-byte size header");
  msg.depth._length = saved._length - 4;  // the last word
  EXPECT_EQ(decodeFrame(msg).error().rfind("depth: RVL payload ends at pixel ", 0), 0u) << decodeFrame(msg).error();
  std::vector<uint8_t> longer(saved._buffer, saved._buffer + saved._length);
  longer.insert(longer.end(), {0, 0, 0, 0});
  msg.depth._buffer = longer.data();
  msg.depth._length = msg.depth._maximum = static_cast<uint32_t>(longer.size());
  EXPECT_EQ(decodeFrame(msg).error(), "depth: RVL payload has 4 bytes after the last pixel");
  msg.depth = saved;
  msg.depth_scale = std::nanf("");
  EXPECT_EQ(decodeFrame(msg).error(), "depth: depth_scale must be finite and > 0 for rvl, got nan");
  msg.depth_scale = 0.001f;
  EXPECT_TRUE(decodeFrame(msg).ok());
}

TEST(FrameCodecPayloads, TruncatedPngsAreRefused) {
  // Cut inside the image data: no partial image may reach the map, for depth as for colour.
  FrameEncoding encoding;
  encoding.depth = "png16";
  encoding.color = "png";
  auto encoded = encodeFrame(makeFrame(), encoding);
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  const auto saved_depth = msg.depth, saved_color = msg.color;
  msg.depth._length = saved_depth._length * 2 / 3;
  auto depth = decodeFrame(msg);
  ASSERT_FALSE(depth.ok());
  EXPECT_EQ(depth.error().rfind("depth: PNG payload does not decode: truncated", 0), 0u) << depth.error();
  msg.depth = saved_depth;
  msg.color._length = saved_color._length * 2 / 3;
  auto color = decodeFrame(msg);
  ASSERT_FALSE(color.ok());
  EXPECT_EQ(color.error().rfind("color: PNG payload does not decode: truncated", 0), 0u) << color.error();
  msg.color = saved_color;
  EXPECT_TRUE(decodeFrame(msg).ok());
}

TEST(FrameCodecPayloads, JpegThatDoesNotDecodeOrHasOtherSize) {
  FrameEncoding encoding;
  encoding.color = "jpeg";
  auto encoded = encodeFrame(makeFrame(), encoding);
  ASSERT_TRUE(encoded.ok());
  auto& msg = encoded.value().msg();
  std::vector<uint8_t> garbage(300, 0x17);
  const auto saved = msg.color;
  msg.color._buffer = garbage.data();
  msg.color._length = msg.color._maximum = 300;
  auto bad = decodeFrame(msg);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error(), "color: JPEG payload does not decode: not a JPEG (no SOI marker)");

  std::vector<uint8_t> small;
  ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(10, 20, CV_8UC3, cv::Scalar(1, 2, 3)), small));
  msg.color._buffer = small.data();
  msg.color._length = msg.color._maximum = static_cast<uint32_t>(small.size());
  auto other = decodeFrame(msg);
  ASSERT_FALSE(other.ok());
  EXPECT_EQ(other.error(), "color: JPEG declares 20x10, frame declares 64x48");

  // Cut short inside its scan: libjpeg alone would fill the rest of the image with grey.
  msg.color = saved;
  msg.color._length = saved._length * 2 / 3;
  auto cut = decodeFrame(msg);
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.error(), "color: JPEG payload does not decode: damaged data (Premature end of JPEG file)");
  msg.color = saved;
}

}  // namespace
}  // namespace semfuse::wire
