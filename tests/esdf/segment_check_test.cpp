// Swept checks of segments (and spheres moved along them) through the fused room.
#include <gtest/gtest.h>

#include "fused_room.hpp"
#include "semfuse/esdf/distance_queries.hpp"

namespace semfuse::esdf::testing {
namespace {

TEST(SegmentCheck, FreeCollidingAndUnknownSegments) {
  const FusedRoom& room = fusedRoom();
  const std::vector<Segment> segments = {
      {{-1.6, -1.0, 1.0}, {-1.6, 0.5, 1.0}},   // across open space at 1 m
      {{0.2, -0.6, 1.0}, {0.2, 0.8, 0.5}},     // down into the table top (z 0.69-0.75)
      {{1.5, 0.0, 1.0}, {3.5, 0.0, 1.0}},      // through the +x wall (x 2.5) into what nobody saw
      {{0.0, 0.0, 5.0}, {0.0, 0.0, 6.0}},      // above the ceiling: never observed
      {{-1.6, -0.5, 1.0}, {-1.6, -0.5, 1.0}},  // a point
  };
  const auto results = checkSegments(*room.esdf, segments, 0.0);
  ASSERT_EQ(results.size(), segments.size());
  EXPECT_EQ(results[0].status, SegmentStatus::kFree);
  EXPECT_FLOAT_EQ(results[0].fraction, 1.0f);
  EXPECT_GT(results[0].min_clearance, 0.3f);
  EXPECT_EQ(results[1].status, SegmentStatus::kCollision);
  EXPECT_NEAR(results[1].blocked_at.z(), 0.75, 2 * kVoxel);  // stopped at the table top
  EXPECT_EQ(results[2].status, SegmentStatus::kCollision);
  EXPECT_NEAR(results[2].blocked_at.x(), 2.5, 2 * kVoxel);  // the cabinet is at y 0.3..1.3: the wall
  EXPECT_EQ(results[3].status, SegmentStatus::kUnknown);
  EXPECT_FLOAT_EQ(results[3].fraction, 0.0f);
  EXPECT_EQ(results[4].status, SegmentStatus::kFree);
}

TEST(SegmentCheck, ASphereCollidesWhereAPointPasses) {
  const FusedRoom& room = fusedRoom();
  // 0.25 m above the table top, parallel to it, clear of the small sphere standing on it.
  const std::vector<Segment> over_table = {{{-0.3, -0.2, 1.0}, {0.7, -0.2, 1.0}}};
  EXPECT_EQ(checkSegments(*room.esdf, over_table, 0.0)[0].status, SegmentStatus::kFree);
  EXPECT_EQ(checkSegments(*room.esdf, over_table, 0.15)[0].status, SegmentStatus::kFree);
  // The small sphere (top at 0.99 m, at x 0.45) is in the way of a 0.15 m ball at 1.1 m.
  const std::vector<Segment> past_sphere = {{{-0.3, 0.25, 1.1}, {1.2, 0.25, 1.1}}};
  const auto point = checkSegments(*room.esdf, past_sphere, 0.0)[0];
  EXPECT_EQ(point.status, SegmentStatus::kFree);
  EXPECT_NEAR(point.min_clearance, 0.11, kVoxel);
  const auto ball = checkSegments(*room.esdf, past_sphere, 0.15)[0];
  EXPECT_EQ(ball.status, SegmentStatus::kCollision);
  EXPECT_NEAR(ball.blocked_at.x(), 0.45, 0.15);
  // A ball as wide as the gap to the table top does not fit.
  EXPECT_EQ(checkSegments(*room.esdf, over_table, 0.3)[0].status, SegmentStatus::kCollision);
}

}  // namespace
}  // namespace semfuse::esdf::testing
