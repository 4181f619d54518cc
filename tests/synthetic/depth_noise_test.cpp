// The depth noise model produces the statistics it is configured with, and only those.
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/synthetic/depth_noise.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"

namespace semfuse::synthetic {
namespace {

const PinholeIntrinsics kSensorCamera{640, 480, 525.0, 525.0, 319.5, 239.5};

// Frontal view of the +x wall from 2 m: every pixel is wall at depth 2.0, incidence up to ~31 deg.
RenderedView frontalWall() {
  return renderView(makeRoom(), kSensorCamera, lookAt({0.5, -0.8, 1.4}, {2.5, -0.8, 1.4})).value();
}

DepthNoiseParams gaussianOnly() {
  DepthNoiseParams p;
  p.disparity_step = 0.0;
  p.dropout_probability = 0.0;
  p.sigma_angular = 0.0;
  return p;
}

TEST(DepthNoise, AxialNoiseHasConfiguredSpread) {
  const RenderedView view = frontalWall();
  const DepthNoiseParams params = gaussianOnly();
  const cv::Mat noisy = applyDepthNoise(view, params, /*seed=*/7);
  const cv::Mat error = noisy - view.depth;
  cv::Scalar mean, stddev;
  cv::meanStdDev(error, mean, stddev, view.depth > 0);
  const double expected = params.sigma_base + params.sigma_quadratic * (2.0 - 0.4) * (2.0 - 0.4);
  EXPECT_NEAR(expected, axialSigma(params, 2.0, 0.0), 1e-15);
  EXPECT_NEAR(stddev[0], expected, 0.03 * expected);  // 300k samples: ~0.1 % sampling error
  EXPECT_NEAR(mean[0], 0.0, 0.05 * expected);
  EXPECT_EQ(cv::countNonZero(noisy), 640 * 480);
}

TEST(DepthNoise, SpreadGrowsWithDistanceSquared) {
  const DepthNoiseParams params;
  EXPECT_LT(axialSigma(params, 1.0, 0.0), axialSigma(params, 2.0, 0.0));
  // Quadratic term: (4 - 0.4)^2 / (2 - 0.4)^2 = 5.0625 times larger.
  EXPECT_NEAR((axialSigma(params, 4.0, 0.0) - params.sigma_base) / (axialSigma(params, 2.0, 0.0) - params.sigma_base),
              5.0625, 1e-9);
  EXPECT_GT(axialSigma(params, 2.0, 1.2), axialSigma(params, 2.0, 0.0));  // grazing is noisier
}

TEST(DepthNoise, DepthIsQuantisedInDisparity) {
  const RenderedView view = frontalWall();
  DepthNoiseParams params = gaussianOnly();
  params.disparity_step = 1.0 / 8.0;
  const cv::Mat noisy = applyDepthNoise(view, params, 3);
  for (int v = 0; v < noisy.rows; v += 37)
    for (int u = 0; u < noisy.cols; u += 41) {
      const double eighths = params.focal_baseline / noisy.at<float>(v, u) * 8.0;
      ASSERT_NEAR(eighths, std::round(eighths), 2e-3) << "pixel " << u << "," << v;
    }
}

TEST(DepthNoise, DropoutsRandomAndAtGrazingAngles) {
  DepthNoiseParams params = gaussianOnly();
  params.dropout_probability = 0.1;
  params.grazing_start_deg = params.grazing_max_deg = 90.0;
  const RenderedView wall = frontalWall();
  const double kept = cv::countNonZero(applyDepthNoise(wall, params, 11)) / (640.0 * 480.0);
  EXPECT_NEAR(kept, 0.9, 0.005);

  // A low camera looking along the floor sees it at grazing angles: those pixels disappear.
  DepthNoiseParams grazing = gaussianOnly();
  const RenderedView low = renderView(makeRoom(), kSensorCamera, lookAt({-2.0, -1.2, 0.25}, {2.4, -1.2, 0.2})).value();
  const cv::Mat noisy = applyDepthNoise(low, grazing, 11);
  int floor_far = 0, floor_far_kept = 0;
  for (int u = 0; u < 640; ++u) {
    // Rays 3.3-3.8 degrees below the horizon meet the floor 3.8-4.4 m away at under 5 degrees.
    const int v = 270;
    if (low.labels.at<uint16_t>(v, u) != labels::kFloor) continue;
    ++floor_far;
    floor_far_kept += noisy.at<float>(v, u) > 0 ? 1 : 0;
  }
  ASSERT_GT(floor_far, 100);
  EXPECT_EQ(floor_far_kept, 0);
}

TEST(DepthNoise, DeterministicPerSeedAndFrame) {
  const RenderedView view = frontalWall();
  const DepthNoiseParams params;
  const cv::Mat a = applyDepthNoise(view, params, 5, 1);
  const cv::Mat b = applyDepthNoise(view, params, 5, 1);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, applyDepthNoise(view, params, 6, 1), cv::NORM_L1), 0.0);
  EXPECT_GT(cv::norm(a, applyDepthNoise(view, params, 5, 2), cv::NORM_L1), 0.0);
}

}  // namespace
}  // namespace semfuse::synthetic
