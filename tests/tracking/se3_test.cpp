#include <cmath>

#include <gtest/gtest.h>

#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Se3, ZeroTwistIsIdentity) {
  EXPECT_TRUE(expSE3(Vector6d::Zero()).matrix().isApprox(Eigen::Matrix4d::Identity(), 1e-15));
}

TEST(Se3, PureTranslationMovesByTheTranslation) {
  Vector6d xi;
  xi << 0.1, -0.2, 0.3, 0.0, 0.0, 0.0;
  const Eigen::Isometry3d T = expSE3(xi);
  EXPECT_TRUE(T.linear().isApprox(Eigen::Matrix3d::Identity(), 1e-15));
  EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(0.1, -0.2, 0.3), 1e-15));
}

TEST(Se3, ExpMatchesTheScrewMotion) {
  // A quarter turn about z with unit velocity along x: the translation is V v, where for
  // theta = pi/2 about z, V = [[sin t/t, -(1-cos t)/t, 0], [(1-cos t)/t, sin t/t, 0], [0, 0, 1]].
  Vector6d xi;
  xi << 1.0, 0.0, 0.0, 0.0, 0.0, kPi / 2;
  const Eigen::Isometry3d T = expSE3(xi);
  const double t = kPi / 2;
  EXPECT_NEAR(T.translation().x(), std::sin(t) / t, 1e-12);
  EXPECT_NEAR(T.translation().y(), (1.0 - std::cos(t)) / t, 1e-12);
  EXPECT_NEAR(T.translation().z(), 0.0, 1e-12);
  EXPECT_NEAR(rotationAngle(T.linear()), t, 1e-12);
}

TEST(Se3, SmallAngleSeriesAgreesWithClosedForm) {
  Vector6d a;
  a << 0.3, 0.1, -0.2, 2e-6, -1e-6, 3e-6;  // series branch
  Vector6d b = a;
  b.tail<3>() *= 10.0;  // closed-form branch, 10x the angle
  // The translation of exp is continuous in the angle: both are within O(theta) of v.
  EXPECT_LT((expSE3(a).translation() - a.head<3>()).norm(), 1e-6);
  EXPECT_LT((expSE3(b).translation() - b.head<3>()).norm(), 1e-5);
}

TEST(Se3, RotationAngleIsAccurateNearZeroAndPi) {
  EXPECT_NEAR(rotationAngle(Eigen::AngleAxisd(1e-7, Eigen::Vector3d::UnitX()).toRotationMatrix()), 1e-7, 1e-12);
  EXPECT_NEAR(rotationAngle(Eigen::AngleAxisd(kPi - 1e-4, Eigen::Vector3d::UnitY()).toRotationMatrix()), kPi - 1e-4,
              1e-9);
}

}  // namespace
}  // namespace semfuse::tracking
