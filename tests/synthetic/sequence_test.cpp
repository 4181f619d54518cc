// The camera stream of the synthetic room: smooth trajectory, consistent frames, determinism.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "semfuse/synthetic/synthetic_sequence.hpp"

namespace semfuse::synthetic {
namespace {

TEST(SyntheticSequence, TrajectoryIsSmoothClosedAndInFreeSpace) {
  const SyntheticSequence sequence;
  const LabeledScene& room = sequence.scene();
  for (int i = 0; i < sequence.frameCount(); ++i) {
    const Pose a = sequence.pose(i), b = sequence.pose(i + 1);
    ASSERT_LT((b.translation() - a.translation()).norm(), 0.05) << "frame " << i;
    ASSERT_LT(Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle(), 3.0 * M_PI / 180) << i;
    ASSERT_GT(room.nearestSurface(a.translation()).signed_distance, 0.3) << "camera in an object, frame " << i;
    ASSERT_TRUE((a.linear().transpose() * a.linear()).isIdentity(1e-12));
  }
  EXPECT_TRUE(sequence.pose(0).isApprox(sequence.pose(sequence.frameCount()), 1e-9));  // periodic
}

TEST(SyntheticSequence, FrameCarriesDepthColourPoseAndGroundTruth) {
  const SyntheticSequence sequence;
  auto both = sequence.frameWithGroundTruth(45);
  ASSERT_TRUE(both.ok()) << both.error();
  const auto& [frame, truth] = both.value();
  EXPECT_EQ(frame.seq, 45u);
  EXPECT_EQ(frame.stamp.sec, 1);
  EXPECT_EQ(frame.stamp.nanosec, 500000000u);
  EXPECT_EQ(frame.depth.type(), CV_32FC1);
  EXPECT_EQ(frame.color.type(), CV_8UC3);
  ASSERT_TRUE(frame.camera_to_world.has_value());
  EXPECT_TRUE(frame.camera_to_world->isApprox(sequence.pose(45)));
  EXPECT_EQ(cv::countNonZero(frame.depth), 640 * 480);  // closed room: every ray hits something
  EXPECT_EQ(truth.frame_seq, 45u);
  EXPECT_EQ(truth.labels.type(), CV_16UC1);
  EXPECT_EQ(cv::countNonZero(truth.labels), 640 * 480);
  double min_conf, max_conf;
  cv::minMaxLoc(truth.confidence, &min_conf, &max_conf);
  EXPECT_EQ(min_conf, 1.0);
  // A view across the room shows several classes.
  double max_label;
  cv::minMaxLoc(truth.labels, nullptr, &max_label);
  EXPECT_GE(max_label, labels::kTable);
  EXPECT_FALSE(sequence.frame(45, /*with_pose=*/false).value().camera_to_world.has_value());
}

TEST(SyntheticSequence, SameSeedSameFramesOtherSeedOtherNoise) {
  SequenceConfig config;
  config.noise = DepthNoiseParams{};
  config.seed = 42;
  config.intrinsics = config.intrinsics.scaled(0.25);  // keep the test quick
  const SyntheticSequence a(config), b(config);
  config.seed = 43;
  const SyntheticSequence c(config);
  const Frame fa = a.frame(10).value(), fb = b.frame(10).value(), fc = c.frame(10).value();
  EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.color, fb.color, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(fa.depth, fc.depth, cv::NORM_L1), 0.0);
  EXPECT_EQ(cv::norm(fa.color, fc.color, cv::NORM_INF), 0.0);  // noise seed leaves colour alone
}

TEST(SyntheticSequence, IndexOutsideTheSequenceIsAnError) {
  const SyntheticSequence sequence;
  auto past_end = sequence.frame(sequence.frameCount());
  ASSERT_FALSE(past_end.ok());
  EXPECT_NE(past_end.error().find("outside [0, 300)"), std::string::npos) << past_end.error();
  EXPECT_FALSE(sequence.groundTruth(-1).ok());
}

}  // namespace
}  // namespace semfuse::synthetic
