// Semantic distance: the KD-tree against brute force, and distances to the fused room's table
// against the table's analytic geometry.
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "fused_room.hpp"
#include "semfuse/esdf/semantic_distance.hpp"

namespace semfuse::esdf::testing {
namespace {

TEST(SurfaceIndex, NearestAgreesWithBruteForce) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-2.0f, 2.0f);
  std::vector<SurfacePoint> points;
  for (int i = 0; i < 5000; ++i) points.push_back({{coordinate(random), coordinate(random), coordinate(random)}, 1});
  const SurfaceIndex index(points);
  EXPECT_FALSE(SurfaceIndex({}).nearest({0, 0, 0}).found);
  for (int q = 0; q < 500; ++q) {
    const Eigen::Vector3f query(coordinate(random), coordinate(random), coordinate(random));
    float best = 1e9f;
    for (const auto& p : points) best = std::min(best, (p.position - query).norm());
    const auto nearest = index.nearest(query);
    ASSERT_TRUE(nearest.found);
    EXPECT_FLOAT_EQ(nearest.distance, best);
  }
}

// The analytic distance to the table (top and legs).
double distanceToTable(const synthetic::LabeledScene& scene, const Eigen::Vector3d& p) {
  double best = 1e9;
  for (const auto& object : scene.objects())
    if (object.label == synthetic::labels::kTable) best = std::min(best, synthetic::signedDistance(object.shape, p));
  return best;
}

TEST(SemanticDistance, DistanceToTheTableMatchesItsGeometry) {
  const FusedRoom& room = fusedRoom();
  const SurfaceIndex table(room.esdf->surfaces().gather({synthetic::labels::kTable}));
  ASSERT_GT(table.size(), 500u);
  // Points in free space around the table, where the table top (seen from above and below) is
  // nearer than its legs (4-6 cm across: thinner than a 5 cm voxel).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> x(-0.5, 0.9), y(-0.4, 0.6), z(0.85, 1.6);
  std::vector<Eigen::Vector3d> points;
  while (points.size() < 2000) {
    const Eigen::Vector3d p(x(random), y(random), z(random));
    if (room.scene.nearestSurface(p).signed_distance > kVoxel) points.push_back(p);
  }
  const auto samples = semanticDistances(table, points);
  double worst = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(samples[i].found);
    EXPECT_EQ(samples[i].label, synthetic::labels::kTable);
    const double truth = distanceToTable(room.scene, points[i]);
    worst = std::max(worst, std::abs(samples[i].distance - truth) / kVoxel);
    // The direction points from the query at the surface point found.
    EXPECT_NEAR(samples[i].direction.norm(), 1.0f, 1e-4f);
    EXPECT_LT((points[i].cast<float>() + samples[i].direction * samples[i].distance - samples[i].surface_point).norm(),
              1e-4f);
  }
  std::printf("semantic distance to the table: worst error %.2f voxels over %zu points\n", worst, points.size());
  EXPECT_LE(worst, 1.5);
  // Straight above the table's middle, the direction is down.
  const auto above = semanticDistances(table, {{0.2, 0.1, 1.25}})[0];
  EXPECT_NEAR(above.distance, 0.5, 1.5 * kVoxel);
  EXPECT_LT(above.direction.z(), -0.95f);
}

TEST(SemanticDistance, LabelSetsAndTheSlice) {
  const FusedRoom& room = fusedRoom();
  const SurfaceIndex chairs(room.esdf->surfaces().gather({synthetic::labels::kChair}));
  const SurfaceIndex chairs_or_table(
      room.esdf->surfaces().gather({synthetic::labels::kChair, synthetic::labels::kTable, synthetic::labels::kChair}));
  const SurfaceIndex table(room.esdf->surfaces().gather({synthetic::labels::kTable}));
  EXPECT_EQ(chairs_or_table.size(), chairs.size() + table.size());
  EXPECT_EQ(SurfaceIndex(room.esdf->surfaces().gather({999})).size(), 0u);
  // The nearest of two labels is the nearer of the two.
  const Eigen::Vector3d p(-0.3, -0.3, 1.0);
  const float a = semanticDistances(chairs, {p})[0].distance, b = semanticDistances(table, {p})[0].distance;
  EXPECT_FLOAT_EQ(semanticDistances(chairs_or_table, {p})[0].distance, std::min(a, b));

  SemanticSliceRequest request;
  request.z = 1.0;
  request.bounds = SliceBounds{{-1.0, -1.0}, {1.0, 0.5}};
  request.resolution = 0.1;
  EXPECT_EQ(semanticSliceCellCount(request), 20u * 15u);
  const SemanticSlice slice = semanticSlice(table, request);
  ASSERT_EQ(slice.distance.cols, 20);
  ASSERT_EQ(slice.distance.rows, 15);
  // Cell (12, 11) has its centre at (0.25, 0.15): over the table top, 0.25 m above it.
  EXPECT_NEAR(slice.distance.at<float>(11, 12), 0.25, 1.5 * kVoxel);
  EXPECT_FLOAT_EQ(slice.distance.at<float>(3, 4), semanticDistances(table, {{-0.55, -0.65, 1.0}})[0].distance);
}

}  // namespace
}  // namespace semfuse::esdf::testing
