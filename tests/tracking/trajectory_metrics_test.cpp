#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "semfuse/tracking/trajectory_metrics.hpp"

namespace semfuse::tracking {
namespace {

std::vector<Pose> helix(int n) {
  std::vector<Pose> poses;
  for (int i = 0; i < n; ++i) {
    Pose p = Pose::Identity();
    p.translation() = Eigen::Vector3d(std::cos(0.1 * i), std::sin(0.1 * i), 0.02 * i);
    p.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    poses.push_back(p);
  }
  return poses;
}

TEST(TrajectoryMetrics, RigidlyMovedCopyHasZeroErrorOnlyAfterAlignment) {
  const std::vector<Pose> reference = helix(50);
  Pose offset = Pose::Identity();
  offset.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  offset.translation() = Eigen::Vector3d(0.5, -0.2, 0.1);
  std::vector<Pose> moved;
  for (const Pose& p : reference) moved.push_back(offset * p);

  auto raw = absoluteTrajectoryError(moved, reference, false);
  auto aligned = absoluteTrajectoryError(moved, reference, true);
  ASSERT_TRUE(raw.ok() && aligned.ok());
  EXPECT_GT(raw.value().rmse_m, 0.2);
  EXPECT_LT(aligned.value().rmse_m, 1e-9);
  EXPECT_TRUE(aligned.value().alignment.isApprox(offset.inverse(), 1e-9));
  // A rigid copy moves every frame exactly like the reference.
  auto rpe = relativePoseError(moved, reference);
  ASSERT_TRUE(rpe.ok());
  EXPECT_LT(rpe.value().translation_max_m, 1e-12);
  EXPECT_LT(rpe.value().rotation_max_deg, 1e-9);
}

TEST(TrajectoryMetrics, ConstantOffsetGivesThatError) {
  const std::vector<Pose> reference = helix(20);
  std::vector<Pose> shifted = reference;
  for (std::size_t i = 10; i < shifted.size(); ++i) shifted[i].translation().x() += 0.03;
  auto ate = absoluteTrajectoryError(shifted, reference, false);
  ASSERT_TRUE(ate.ok());
  EXPECT_NEAR(ate.value().rmse_m, 0.03 * std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(ate.value().max_m, 0.03, 1e-12);
  auto rpe = relativePoseError(shifted, reference);
  ASSERT_TRUE(rpe.ok());
  EXPECT_NEAR(rpe.value().translation_max_m, 0.03, 1e-12);  // the one jump at frame 10
}

TEST(TrajectoryMetrics, MismatchedTrajectoriesAreRejected) {
  auto ate = absoluteTrajectoryError(helix(5), helix(6), false);
  ASSERT_FALSE(ate.ok());
  EXPECT_NE(ate.error().find("differ in length"), std::string::npos);
  EXPECT_FALSE(relativePoseError(helix(1), helix(1)).ok());
  EXPECT_NEAR(pathLength(helix(2)), std::hypot(std::cos(0.1) - 1.0, std::sin(0.1), 0.02), 1e-12);
}

}  // namespace
}  // namespace semfuse::tracking
