#include "semfuse/wire/ros_codec.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace semfuse::wire {
namespace {

TEST(RosImage, Depth16UC1IsMillimetres) {
  cv::Mat mm(2, 3, CV_16UC1);
  mm = cv::Scalar(1500);
  mm.at<uint16_t>(1, 2) = 0;
  auto image = matToImage(mm, "16UC1", {1, 2}, "depth_optical");
  ASSERT_TRUE(image.ok()) << image.error();
  EXPECT_EQ(image.value().msg().step, 6u);
  EXPECT_STREQ(image.value().msg().header.frame_id, "depth_optical");
  auto metres = depthImageToMetres(image.value().msg());
  ASSERT_TRUE(metres.ok()) << metres.error();
  EXPECT_FLOAT_EQ(metres.value().at<float>(0, 0), 1.5f);
  EXPECT_FLOAT_EQ(metres.value().at<float>(1, 2), 0.0f);
}

TEST(RosImage, Bgr8ComesOutRgbAndPaddedRowsAreHonoured) {
  // 2x2 bgr8 with a 2-byte pad per row (step 8).
  std::vector<uint8_t> data = {10, 20, 30, 11, 21, 31, 0, 0, 12, 22, 32, 13, 23, 33, 0, 0};
  sensor_msgs_msg_dds__Image_ msg{};
  msg.width = 2;
  msg.height = 2;
  msg.encoding = const_cast<char*>("bgr8");
  msg.step = 8;
  msg.data = {static_cast<uint32_t>(data.size()), static_cast<uint32_t>(data.size()), data.data(), false};
  auto mat = imageToMat(msg);
  ASSERT_TRUE(mat.ok()) << mat.error();
  EXPECT_EQ(mat.value().at<cv::Vec3b>(0, 0), cv::Vec3b(30, 20, 10));
  EXPECT_EQ(mat.value().at<cv::Vec3b>(1, 1), cv::Vec3b(33, 23, 13));
  msg.step = 5;
  EXPECT_EQ(imageToMat(msg).error(), "image: step 5 shorter than a row of 2 bgr8 pixels (6 bytes)");
  msg.step = 8;
  msg.data._length = 15;
  EXPECT_EQ(imageToMat(msg).error(), "image: 15 bytes for 2x2 bgr8 with step 8, expected 16");
  msg.encoding = const_cast<char*>("yuv422");
  EXPECT_NE(imageToMat(msg).error().find("image: unknown encoding 'yuv422' (known: 16UC1, mono16, 32FC1"),
            std::string::npos);
}

TEST(RosImage, BigEndianMono16IsSwapped) {
  std::vector<uint8_t> data = {0x05, 0xDC};  // 1500 big-endian
  sensor_msgs_msg_dds__Image_ msg{};
  msg.width = 1;
  msg.height = 1;
  msg.encoding = const_cast<char*>("mono16");
  msg.is_bigendian = 1;
  msg.step = 2;
  msg.data = {2, 2, data.data(), false};
  auto metres = depthImageToMetres(msg);
  ASSERT_TRUE(metres.ok()) << metres.error();
  EXPECT_FLOAT_EQ(metres.value().at<float>(0, 0), 1.5f);
}

TEST(RosImage, Float32RoundTripAndTypeMismatch) {
  cv::Mat metres(3, 2, CV_32FC1, cv::Scalar(2.25f));
  auto image = matToImage(metres, "32FC1", {}, "");
  ASSERT_TRUE(image.ok());
  auto back = imageToMat(image.value().msg());
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(cv::norm(metres, back.value(), cv::NORM_INF), 0.0);
  EXPECT_EQ(matToImage(metres, "rgb8", {}, "").error(), "image: a 32FC1 image cannot be sent as rgb8 (needs 8UC3)");
}

TEST(RosCompressedImage, PngAndJpeg) {
  cv::Mat bgr(4, 5, CV_8UC3, cv::Scalar(10, 20, 30));
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", bgr, png));
  sensor_msgs_msg_dds__CompressedImage_ msg{};
  msg.format = const_cast<char*>("rgb8; png compressed bgr8");
  msg.data = {static_cast<uint32_t>(png.size()), static_cast<uint32_t>(png.size()), png.data(), false};
  auto rgb = compressedImageToMat(msg);
  ASSERT_TRUE(rgb.ok()) << rgb.error();
  EXPECT_EQ(rgb.value().at<cv::Vec3b>(3, 4), cv::Vec3b(30, 20, 10));

  std::vector<uint8_t> garbage(50, 1);
  msg.format = const_cast<char*>("jpeg");
  msg.data = {50, 50, garbage.data(), false};
  EXPECT_EQ(compressedImageToMat(msg).error(),
            "compressed image: JPEG payload does not decode: not a JPEG (no SOI marker)");
  msg.format = const_cast<char*>("tiff");
  EXPECT_EQ(compressedImageToMat(msg).error(), "compressed image: unknown format 'tiff' (known: jpeg, png)");
}

TEST(RosCompressedImage, JpegKeepsItsChannelCount) {
  cv::Mat bgr(16, 24, CV_8UC3);
  cv::randu(bgr, 0, 255);
  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", bgr, jpeg));
  sensor_msgs_msg_dds__CompressedImage_ msg{};
  msg.format = const_cast<char*>("bgr8; jpeg compressed bgr8");
  msg.data = {static_cast<uint32_t>(jpeg.size()), static_cast<uint32_t>(jpeg.size()), jpeg.data(), false};
  auto rgb = compressedImageToMat(msg);
  ASSERT_TRUE(rgb.ok()) << rgb.error();
  cv::Mat expected;
  cv::cvtColor(cv::imdecode(jpeg, cv::IMREAD_COLOR), expected, cv::COLOR_BGR2RGB);
  ASSERT_EQ(rgb.value().type(), CV_8UC3);
  EXPECT_EQ(cv::norm(rgb.value(), expected, cv::NORM_INF), 0.0);

  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  ASSERT_TRUE(cv::imencode(".jpg", grey, jpeg));
  msg.format = const_cast<char*>("mono8; jpeg compressed mono8");
  msg.data = {static_cast<uint32_t>(jpeg.size()), static_cast<uint32_t>(jpeg.size()), jpeg.data(), false};
  auto mono = compressedImageToMat(msg);
  ASSERT_TRUE(mono.ok()) << mono.error();
  ASSERT_EQ(mono.value().type(), CV_8UC1);
  EXPECT_EQ(cv::norm(mono.value(), cv::imdecode(jpeg, cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
}

TEST(RosCameraInfo, KnownValuesBothWays) {
  const PinholeIntrinsics k{640, 480, 585.0, 586.0, 320.5, 240.25};
  auto info = cameraInfoFromIntrinsics(k, {7, 8}, "cam");
  EXPECT_DOUBLE_EQ(info.msg().k[0], 585.0);
  EXPECT_DOUBLE_EQ(info.msg().k[2], 320.5);
  EXPECT_DOUBLE_EQ(info.msg().k[4], 586.0);
  EXPECT_DOUBLE_EQ(info.msg().k[5], 240.25);
  EXPECT_DOUBLE_EQ(info.msg().k[8], 1.0);
  EXPECT_DOUBLE_EQ(info.msg().p[0], 585.0);
  EXPECT_STREQ(info.msg().distortion_model, "plumb_bob");
  EXPECT_EQ(stampOf(info.msg().header).sec, 7);
  auto back = intrinsicsFromCameraInfo(info.msg());
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back.value().width, 640);
  EXPECT_DOUBLE_EQ(back.value().fy, 586.0);
  EXPECT_DOUBLE_EQ(back.value().cy, 240.25);
  info.msg().k[0] = 0.0;
  EXPECT_EQ(intrinsicsFromCameraInfo(info.msg()).error(),
            "camera info: intrinsics: focal lengths must be finite and > 0, got fx=0 fy=586");
}

TEST(RosTransform, QuaternionToRotationAndBack) {
  geometry_msgs_msg_dds__Transform_ transform{};
  transform.translation = {1.0, 2.0, 3.0};
  // 90 degrees about z.
  transform.rotation = {0.0, 0.0, std::sqrt(0.5), std::sqrt(0.5)};
  auto pose = poseFromTransform(transform);
  ASSERT_TRUE(pose.ok()) << pose.error();
  EXPECT_TRUE((pose.value() * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(1, 3, 3)));
  auto back = transformFromPose(pose.value(), {}, "world", "camera");
  EXPECT_NEAR(back.msg().transform.rotation.z, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(back.msg().transform.rotation.w, std::sqrt(0.5), 1e-12);
  EXPECT_DOUBLE_EQ(back.msg().transform.translation.y, 2.0);
  EXPECT_STREQ(back.msg().child_frame_id, "camera");
  transform.rotation = {0.0, 0.0, 0.0, 0.5};
  EXPECT_EQ(poseFromTransform(transform).error(), "transform: quaternion norm 0.500000 is not 1");
}

}  // namespace
}  // namespace semfuse::wire
