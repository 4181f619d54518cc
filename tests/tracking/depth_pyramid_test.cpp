#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "semfuse/tracking/depth_pyramid.hpp"

namespace semfuse::tracking {
namespace {

PinholeIntrinsics camera(int width, int height) {
  return {width, height, 585.0 * width / 640.0, 585.0 * width / 640.0, width / 2.0, height / 2.0};
}

TEST(DepthPyramid, HalvesResolutionAndIntrinsicsPerLevel) {
  const PinholeIntrinsics k = camera(640, 480);
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  DepthPyramid pyramid;
  ASSERT_TRUE(pyramid.build(depth, k, {}).ok());
  ASSERT_EQ(pyramid.levels(), 3);
  EXPECT_EQ(pyramid.depth(2).cols, 160);
  EXPECT_EQ(pyramid.depth(2).rows, 120);
  EXPECT_DOUBLE_EQ(pyramid.intrinsics(1).fx, k.fx / 2);
  EXPECT_DOUBLE_EQ(pyramid.intrinsics(2).cx, (k.cx + 0.5) / 4 - 0.5);
  EXPECT_FLOAT_EQ(pyramid.depth(2).at<float>(60, 80), 2.0f);
  EXPECT_NEAR(pyramid.meanDepth(), 2.0, 1e-6);
}

TEST(DepthPyramid, DownsamplingKeepsTheForegroundAtDepthEdges) {
  // Columns 0-4 at 1 m, 5-15 at 3 m: the edge falls inside the 2x2 blocks of columns 4-5.
  cv::Mat depth(16, 16, CV_32FC1, cv::Scalar(3.0f));
  depth.colRange(0, 5).setTo(1.0f);
  PyramidParams params;
  params.levels = 2;
  params.max_points = {0, 0, 0, 0};
  DepthPyramid pyramid;
  ASSERT_TRUE(pyramid.build(depth, camera(16, 16), params).ok());
  // An average of the block would read 2 m, a surface that does not exist.
  EXPECT_FLOAT_EQ(pyramid.depth(1).at<float>(0, 2), 1.0f);
  EXPECT_FLOAT_EQ(pyramid.depth(1).at<float>(0, 3), 3.0f);
}

TEST(DepthPyramid, InvalidReadingsNeitherBecomePointsNorPoisonAverages) {
  cv::Mat depth(16, 16, CV_32FC1, cv::Scalar(2.0f));
  depth.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(0, 1) = std::numeric_limits<float>::infinity();
  depth.at<float>(1, 0) = 0.0f;
  depth.at<float>(5, 5) = 60.0f;  // beyond max_depth
  PyramidParams params;
  params.levels = 2;
  params.max_points = {0, 0, 0, 0};
  DepthPyramid pyramid;
  ASSERT_TRUE(pyramid.build(depth, camera(16, 16), params).ok());
  EXPECT_EQ(pyramid.validPixels(0), 256u - 4u);
  EXPECT_EQ(pyramid.points(0).size(), 256u - 4u);
  EXPECT_FLOAT_EQ(pyramid.depth(1).at<float>(0, 0), 2.0f);  // one valid reading left in the block
  for (const Eigen::Vector3f& p : pyramid.points(0)) ASSERT_TRUE(p.allFinite());
}

TEST(DepthPyramid, SubsamplesToTheRequestedPointBudget) {
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(1.5f));
  PyramidParams params;
  params.max_points = {5000, 5000, 50000, 0};
  DepthPyramid pyramid;
  ASSERT_TRUE(pyramid.build(depth, camera(640, 480), params).ok());
  EXPECT_LE(pyramid.points(0).size(), 5000u);
  EXPECT_GT(pyramid.points(0).size(), 2500u);  // the stride is the smallest that fits
  EXPECT_EQ(pyramid.points(2).size(), 160u * 120u);
  // Back-projection: the point of pixel (u, v) lies on that pixel's ray at the reading's depth.
  const Eigen::Vector3f& p = pyramid.points(2).front();
  EXPECT_FLOAT_EQ(p.z(), 1.5f);
  const PinholeIntrinsics& k = pyramid.intrinsics(2);
  EXPECT_NEAR(p.x() / p.z() * k.fx + k.cx, 0.0, 1e-4);
}

TEST(DepthPyramid, RejectsMalformedInputWithTheReason) {
  DepthPyramid pyramid;
  const PinholeIntrinsics k = camera(64, 48);
  Status empty = pyramid.build(cv::Mat(), k, {});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("empty"), std::string::npos);

  Status type = pyramid.build(cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)), k, {});
  ASSERT_FALSE(type.ok());
  EXPECT_NE(type.error().find("CV_32FC1"), std::string::npos);

  PyramidParams too_many;
  too_many.levels = kMaxPyramidLevels + 1;
  Status levels = pyramid.build(cv::Mat(48, 64, CV_32FC1, cv::Scalar(1.0f)), k, too_many);
  ASSERT_FALSE(levels.ok());
  EXPECT_NE(levels.error().find("levels"), std::string::npos);

  Status size = pyramid.build(cv::Mat(40, 64, CV_32FC1, cv::Scalar(1.0f)), k, {});
  ASSERT_FALSE(size.ok());
  EXPECT_NE(size.error().find("64x40"), std::string::npos);

  PinholeIntrinsics bad = k;
  bad.fx = 0.0;
  EXPECT_FALSE(pyramid.build(cv::Mat(48, 64, CV_32FC1, cv::Scalar(1.0f)), bad, {}).ok());

  PyramidParams deep;
  deep.levels = 4;
  Status small = pyramid.build(cv::Mat(48, 64, CV_32FC1, cv::Scalar(1.0f)), k, deep);
  ASSERT_FALSE(small.ok());
  EXPECT_NE(small.error().find("too small"), std::string::npos);
}

}  // namespace
}  // namespace semfuse::tracking
