// CameraPublisher -> a plain DDS reader on rt/semfuse/frames: the frame arrives field for field.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include SEMFUSE_DDS_TEST_ENV
#include "semfuse/client/camera_publisher.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/frame_codec.hpp"

namespace semfuse::client {
namespace {

using FrameMsg = semfuse_msg_dds__Frame_;

Frame testFrame() {
  Frame f;
  f.camera_id = "kitchen-cam";
  f.seq = 1234;
  f.stamp = {17, 250000000};
  f.intrinsics = {64, 48, 60.0, 61.0, 31.5, 23.5};
  f.depth.create(48, 64, CV_32FC1);
  f.color.create(48, 64, CV_8UC3);
  for (int r = 0; r < 48; ++r) {
    for (int c = 0; c < 64; ++c) {
      f.depth.at<float>(r, c) = (r == 5 && c == 7) ? 0.0F : 0.5F + 0.01F * r + 0.0023F * c;  // one hole
      f.color.at<cv::Vec3b>(r, c) = {static_cast<uchar>(4 * c), static_cast<uchar>(5 * r), 90};
    }
  }
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(1.5, -0.25, 1.2);
  f.camera_to_world = pose;
  return f;
}

class CameraPublisherTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dds::testing::useLoopbackConfig(); }

  // Publishes `frame` and returns what a plain reader of the frames topic took.
  dds::Sample<FrameMsg> roundTrip(const Frame& frame, CameraPublisherOptions options) {
    dds::Topic<FrameMsg> topic(participant_, dds::topics::kFrames);
    dds::Reader<FrameMsg> reader(topic, dds::qos::frames());
    CameraPublisher camera(participant_, options);
    EXPECT_TRUE(camera.waitForReader(std::chrono::seconds(15)));
    EXPECT_EQ(camera.matchedReaders(), 1);
    const Status published = camera.publish(frame);
    EXPECT_TRUE(published.ok()) << published.error();
    EXPECT_TRUE(camera.waitForAcknowledgements(std::chrono::seconds(15)).ok());
    auto sample = reader.take();
    if (!sample) {
      ADD_FAILURE() << "the reader got no frame";
      return dds::Sample<FrameMsg>();
    }
    return std::move(*sample);
  }

  dds::Participant participant_{dds::testing::testDomain()};
};

TEST_F(CameraPublisherTest, RawEncodingsArriveFieldForField) {
  const Frame frame = testFrame();
  const auto msg = roundTrip(frame, {DepthEncoding::kRaw16, ColorEncoding::kRaw, 90});
  EXPECT_STREQ(msg->camera_id, "kitchen-cam");
  EXPECT_EQ(msg->seq, 1234u);
  EXPECT_EQ(msg->header.stamp.sec, 17);
  EXPECT_EQ(msg->header.stamp.nanosec, 250000000u);
  EXPECT_EQ(msg->intrinsics.width, 64u);
  EXPECT_EQ(msg->intrinsics.height, 48u);
  EXPECT_DOUBLE_EQ(msg->intrinsics.fx, 60.0);
  EXPECT_DOUBLE_EQ(msg->intrinsics.fy, 61.0);
  EXPECT_DOUBLE_EQ(msg->intrinsics.cx, 31.5);
  EXPECT_DOUBLE_EQ(msg->intrinsics.cy, 23.5);
  EXPECT_STREQ(msg->depth_encoding, "16UC1");
  EXPECT_FLOAT_EQ(msg->depth_scale, 0.001F);
  ASSERT_EQ(msg->depth._length, 64u * 48u * 2u);
  const auto* mm = reinterpret_cast<const uint16_t*>(msg->depth._buffer);
  EXPECT_EQ(mm[0], 500);         // 0.5 m
  EXPECT_EQ(mm[5 * 64 + 7], 0);  // the hole stays invalid
  EXPECT_EQ(mm[47 * 64 + 63], std::lround((0.5F + 0.47F + 0.0023F * 63) * 1000.0F));
  EXPECT_STREQ(msg->color_encoding, "rgb8");
  ASSERT_EQ(msg->color._length, 64u * 48u * 3u);
  EXPECT_EQ(msg->color._buffer[(10 * 64 + 20) * 3 + 0], 80);  // R = 4c
  EXPECT_EQ(msg->color._buffer[(10 * 64 + 20) * 3 + 1], 50);  // G = 5r
  EXPECT_EQ(msg->color._buffer[(10 * 64 + 20) * 3 + 2], 90);
  ASSERT_TRUE(msg->has_pose);
  const Eigen::Matrix<double, 3, 4> expected = frame.camera_to_world->matrix().topRows<3>();
  for (int i = 0; i < 12; ++i) EXPECT_DOUBLE_EQ(msg->camera_to_world[i], expected(i / 4, i % 4)) << i;

  auto decoded = wire::decodeFrame(*msg);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_EQ(cv::norm(decoded.value().color, frame.color, cv::NORM_INF), 0.0);  // raw RGB is exact
  EXPECT_LE(cv::norm(decoded.value().depth, frame.depth, cv::NORM_INF), 0.0005 + 1e-6);
}

TEST_F(CameraPublisherTest, CompressedEncodingsAndNoPoseDecodeToTheSameFrame) {
  Frame frame = testFrame();
  frame.camera_to_world.reset();
  const auto msg = roundTrip(frame, {DepthEncoding::kPng16, ColorEncoding::kJpeg, 95});
  EXPECT_STREQ(msg->depth_encoding, "png16");
  EXPECT_STREQ(msg->color_encoding, "jpeg");
  EXPECT_FALSE(msg->has_pose);
  EXPECT_LT(msg->color._length, 64u * 48u * 3u) << "JPEG should be smaller than raw";
  auto decoded = wire::decodeFrame(*msg);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_FALSE(decoded.value().camera_to_world.has_value());
  EXPECT_LE(cv::norm(decoded.value().depth, frame.depth, cv::NORM_INF), 0.0005 + 1e-6);         // PNG is lossless in mm
  EXPECT_LT(cv::norm(decoded.value().color, frame.color, cv::NORM_L1) / (64.0 * 48 * 3), 3.0);  // JPEG is close
}

TEST_F(CameraPublisherTest, RvlDepthIsLosslessMillimetresAndSmallerThanRaw) {
  const Frame frame = testFrame();
  ASSERT_EQ(parseDepthEncoding("rvl"), DepthEncoding::kRvl);
  const auto msg = roundTrip(frame, {DepthEncoding::kRvl, ColorEncoding::kNone, 90});
  EXPECT_STREQ(msg->depth_encoding, "rvl");
  EXPECT_FLOAT_EQ(msg->depth_scale, 0.001F);
  EXPECT_STREQ(msg->color_encoding, "");
  EXPECT_LT(msg->depth._length, 64u * 48u * 2u / 2u) << "a smooth ramp takes about a nibble a pixel";
  auto decoded = wire::decodeFrame(*msg);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  // The same millimetres as the raw encoding gives.
  const auto raw = roundTrip(frame, {DepthEncoding::kRaw16, ColorEncoding::kNone, 90});
  auto raw_decoded = wire::decodeFrame(*raw);
  ASSERT_TRUE(raw_decoded.ok()) << raw_decoded.error();
  EXPECT_EQ(cv::norm(decoded.value().depth, raw_decoded.value().depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(decoded.value().depth.at<float>(5, 7), 0.0F);  // the hole
}

TEST_F(CameraPublisherTest, RejectsAFrameThatIsNotDepthInMetres) {
  Frame frame = testFrame();
  frame.depth.convertTo(frame.depth, CV_16UC1, 1000.0);
  CameraPublisher camera(participant_, {});
  EXPECT_FALSE(camera.publish(frame).ok());
}

TEST_F(CameraPublisherTest, RefusesACameraTheServerWouldRefuseBeforeSending) {
  CameraPublisher camera(participant_, {});
  Frame no_focal = testFrame();
  no_focal.intrinsics.fx = 0.0;
  Status refused = camera.publish(no_focal);
  EXPECT_EQ(refused.error(), "intrinsics: focal lengths must be finite and > 0, got fx=0 fy=61");
  EXPECT_EQ(refused.errorCode(), ErrorCode::kInvalidArgument);
  Frame skewed = testFrame();
  skewed.camera_to_world->linear()(0, 1) = 0.3;
  refused = camera.publish(skewed);
  EXPECT_EQ(refused.error().rfind("pose: rotation is not orthonormal", 0), 0u) << refused.error();
  EXPECT_EQ(refused.errorCode(), ErrorCode::kInvalidArgument);
}

TEST_F(CameraPublisherTest, WaitsForTheServersReaderNotJustAnyReader) {
  CameraPublisher camera(participant_, {});
  // A segmenter-like participant: it reads frames but is no server.
  dds::Participant segmenter(dds::testing::testDomain());
  dds::Topic<FrameMsg> segmenter_topic(segmenter, dds::topics::kFrames);
  dds::Reader<FrameMsg> segmenter_frames(segmenter_topic, dds::qos::frames());
  ASSERT_TRUE(camera.waitForReader(std::chrono::seconds(15)));
  EXPECT_FALSE(camera.waitForServer(std::chrono::milliseconds(300)));

  // A server-like participant: it publishes its status and reads frames.
  dds::Participant server(dds::testing::testDomain());
  dds::Topic<semfuse_msg_dds__ServerStatus_> status_topic(server, dds::topics::kStatus);
  dds::Writer<semfuse_msg_dds__ServerStatus_> status(status_topic, dds::qos::status());
  dds::Sample<semfuse_msg_dds__ServerStatus_> sample;
  ASSERT_TRUE(status.write(*sample).ok());
  dds::Topic<FrameMsg> server_topic(server, dds::topics::kFrames);
  dds::Reader<FrameMsg> server_frames(server_topic, dds::qos::frames());
  EXPECT_TRUE(camera.waitForServer(std::chrono::seconds(15)));
}

}  // namespace
}  // namespace semfuse::client
