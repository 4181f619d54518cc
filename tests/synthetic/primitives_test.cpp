// Exact ray intersection and signed distance of each primitive, against hand-computed values.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "semfuse/synthetic/primitives.hpp"

namespace semfuse::synthetic {
namespace {

TEST(Primitives, RayEntersAxisAlignedBoxOnNearFace) {
  const OrientedBox box{{2, 0, 0}, {0.5, 1, 1}, Eigen::Matrix3d::Identity()};
  const auto hit = intersect(box, Ray{{0, 0, 0}, {1, 0, 0}});
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->t, 1.5);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_FALSE(intersect(box, Ray{{0, 0, 0}, {-1, 0, 0}}));  // pointing away
  EXPECT_FALSE(intersect(box, Ray{{2, 0, 0}, {1, 0, 0}}));   // starts inside
}

TEST(Primitives, RotatedBoxUsesItsOwnAxes) {
  // A unit cube turned 45 degrees about z: its edge faces the ray at distance sqrt(2)/2.
  const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const OrientedBox box{{3, 0, 0}, {0.5, 0.5, 0.5}, r};
  const auto hit = intersect(box, Ray{{0, 0.01, 0}, {1, 0, 0}});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 3 - std::sqrt(0.5) + 0.01, 1e-9);
  EXPECT_NEAR(signedDistance(box, {0, 0, 0}), 3 - std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(signedDistance(box, {3, 0, 0}), -0.5, 1e-12);
}

TEST(Primitives, SphereEntryAndDistance) {
  const Sphere sphere{{0, 0, 5}, 1.0};
  const auto hit = intersect(sphere, Ray{{0, 0, 0}, {0, 0, 2}});  // t counts direction lengths
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->t, 2.0);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d(0, 0, -1)));
  EXPECT_FALSE(intersect(sphere, Ray{{0, 1.01, 0}, {0, 0, 1}}));
  EXPECT_DOUBLE_EQ(signedDistance(sphere, {0, 3, 5}), 2.0);
}

TEST(Primitives, CylinderMantleCapAndDistance) {
  const UprightCylinder cyl{{0, 0}, 0.5, 0.0, 2.0};
  const auto side = intersect(cyl, Ray{{-3, 0, 1}, {1, 0, 0}});
  ASSERT_TRUE(side);
  EXPECT_DOUBLE_EQ(side->t, 2.5);
  EXPECT_TRUE(side->normal.isApprox(Eigen::Vector3d(-1, 0, 0)));
  const auto cap = intersect(cyl, Ray{{0.2, 0, 5}, {0, 0, -1}});
  ASSERT_TRUE(cap);
  EXPECT_DOUBLE_EQ(cap->t, 3.0);
  EXPECT_TRUE(cap->normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_FALSE(intersect(cyl, Ray{{-3, 0, 2.5}, {1, 0, 0}}));  // passes over the top
  EXPECT_DOUBLE_EQ(signedDistance(cyl, {2, 0, 1}), 1.5);
  EXPECT_DOUBLE_EQ(signedDistance(cyl, {0, 0, 3}), 1.0);
  EXPECT_NEAR(signedDistance(cyl, {1.5, 0, 3}), std::sqrt(2.0), 1e-12);  // past the rim
  EXPECT_NEAR(signedDistance(cyl, {0, 0, 1.9}), -0.1, 1e-12);
}

}  // namespace
}  // namespace semfuse::synthetic
