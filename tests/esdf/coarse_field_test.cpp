// A distance field coarser than the map: the fused room's field at twice the map's voxel (10 cm
// over 5 cm), which reads the TSDF at every other voxel (copyChanges with a stride). It must
// measure the same surface as the full-resolution field, to within one of its own voxels, keep
// unknown space unknown, and agree with a rebuild; the parameters refuse a voxel that is no whole
// multiple of the map's or larger than the truncation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "field_checks.hpp"
#include "fused_room.hpp"
#include "semfuse/esdf/distance_queries.hpp"
#include "semfuse/esdf/semantic_distance.hpp"

namespace semfuse::esdf::testing {
namespace {

Eigen::Vector3d coarseCentre(const openvdb::Coord& ijk) {
  return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * kCoarseVoxel;
}

TEST(CoarseField, WithinOneOfItsVoxelsOfTheFullResolutionSurface) {
  const FusedRoom& room = fusedRoom();
  const EsdfMap& coarse = *room.coarse;
  EXPECT_DOUBLE_EQ(coarse.voxelSize(), kCoarseVoxel);
  // Eight times fewer voxels than the full field, give or take the edges of observed space.
  EXPECT_LT(coarse.knownVoxels(), room.esdf->knownVoxels() / 6);
  EXPECT_GT(coarse.knownVoxels(), room.esdf->knownVoxels() / 10);
  const SurfaceIndex crossings(tsdfCrossings(*room.volume));
  Errors errors;
  for (auto it = coarse.grid().tree().cbeginValueOn(); it; ++it) {
    const EsdfVoxel v = unpackEsdf(*it);
    if (v.inside || !v.has_site) continue;
    const auto exact = crossings.nearest(coarseCentre(it.getCoord()).cast<float>());
    if (exact.distance > kMaxDistance - kCoarseVoxel) continue;
    errors.values.push_back(std::abs(v.signedDistance(coarse.maxDistanceVoxels()) * kCoarseVoxel - exact.distance) /
                            kCoarseVoxel);
  }
  const double p50 = errors.percentile(50), p99 = errors.percentile(99), worst = errors.percentile(100);
  const auto over = std::count_if(errors.values.begin(), errors.values.end(), [](double e) { return e > 1.0; });
  std::printf(
      "coarse field against the full-resolution crossings: %zu voxels, error median %.3f, p99 %.3f, max %.3f of its "
      "voxels; %zu over one\n",
      errors.values.size(), p50, p99, worst, static_cast<std::size_t>(over));
  EXPECT_GT(errors.values.size(), 20000u);
  EXPECT_LT(p50, 0.15);
  EXPECT_LE(p99, 1.0);
  // Where a surface was seen only in a sliver (the ceiling above the orbits, the walls' upper
  // edges, the floor at the room's corners), the full-resolution TSDF has crossings between voxels
  // of which the coarse field's samples, every other one, are not both observed: it measures to
  // the surface it does see there, up to 2.4 of its voxels farther (135 voxels, 0.34 %).
  EXPECT_LE(static_cast<std::size_t>(over), errors.values.size() / 200);
  EXPECT_LE(worst, 2.5);
}

TEST(CoarseField, AnswersQueriesInMetresLikeTheFullField) {
  const FusedRoom& room = fusedRoom();
  const std::vector<Eigen::Vector3d> points{{-0.6, -1.5, 0.3}, {0.0, 0.3, 1.0}, {0.0, 0.0, 1.3}};
  const auto fine = distancesAt(*room.esdf, points);
  const auto coarse = distancesAt(*room.coarse, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(fine[i].known && coarse[i].known) << i;
    EXPECT_NEAR(coarse[i].distance, fine[i].distance, kCoarseVoxel) << i;
    EXPECT_GT(coarse[i].gradient.dot(fine[i].gradient), 0.9f) << i;
  }
  // Unknown stays unknown: behind the walls, inside the cabinet, above the ceiling.
  for (const DistanceSample& s : distancesAt(*room.coarse, {{3.4, 0.0, 1.0}, {2.28, 0.8, 0.9}, {0.0, 0.0, 5.0}}))
    EXPECT_FALSE(s.known);
}

TEST(CoarseField, IncrementalUpdatesAgreeWithARebuild) {
  const FusedRoom& room = fusedRoom();
  EsdfMap rebuilt(kCoarseVoxel, coarseEsdfParams());
  rebuilt.apply(copyChanges(*room.volume, 0, kCoarseStride));
  // A leaf is copied whenever one of its samples or its halo lies in a changed map leaf: the
  // frame-by-frame field knows exactly the voxels a rebuild does.
  ASSERT_EQ(rebuilt.knownVoxels(), room.coarse->knownVoxels());
  const FieldDifference d = compareFields(*room.coarse, rebuilt);
  EXPECT_EQ(d.missing, 0u);
  std::printf("coarse incremental vs rebuild: %zu voxels, %zu differ by more than 0.5 voxel, worst %.2f\n", d.compared,
              d.differ, d.worst);
  EXPECT_LT(d.differ, d.compared / 50);
  EXPECT_LE(d.worst, 2.0);
}

TEST(CoarseField, ParametersRefuseAVoxelTheMapCannotFeed) {
  EsdfParams params;
  params.voxel_size = 0.04;
  EXPECT_TRUE(params.validate(0.01, 0.04).ok());
  EXPECT_EQ(params.stride(0.01, 0.04), 4);
  EXPECT_DOUBLE_EQ(params.fieldVoxel(0.01, 0.04), 0.04);
  params.voxel_size = 0.01;  // the map's own
  EXPECT_TRUE(params.validate(0.01, 0.04).ok());
  EXPECT_EQ(params.stride(0.01, 0.04), 1);
  params.voxel_size = 0.025;
  const Status not_multiple = params.validate(0.01, 0.04);
  ASSERT_FALSE(not_multiple.ok());
  EXPECT_NE(not_multiple.error().find("whole multiple"), std::string::npos) << not_multiple.error();
  params.voxel_size = 0.05;
  const Status beyond_band = params.validate(0.01, 0.04);
  ASSERT_FALSE(beyond_band.ok());
  EXPECT_NE(beyond_band.error().find("truncation"), std::string::npos) << beyond_band.error();
  params.voxel_size = 0.005;  // finer than the map: nothing to read it from
  EXPECT_FALSE(params.validate(0.01, 0.04).ok());
  params.voxel_size = -0.02;
  EXPECT_FALSE(params.validate(0.01, 0.04).ok());
}

// 0 (the default) takes the coarsest whole multiple of the map's voxel within the truncation and
// 5 cm.
TEST(CoarseField, TheDefaultVoxelIsTheCoarsestTheMapCanFeedUpTo5cm) {
  const EsdfParams automatic;
  EXPECT_DOUBLE_EQ(automatic.fieldVoxel(0.01, 0.04), 0.04);  // the server's default map
  EXPECT_EQ(automatic.stride(0.01, 0.04), 4);
  EXPECT_DOUBLE_EQ(automatic.fieldVoxel(0.01, 0.08), 0.05);
  EXPECT_DOUBLE_EQ(automatic.fieldVoxel(0.02, 0.08), 0.04);
  EXPECT_EQ(automatic.stride(0.05, 0.1), 1);  // a 5 cm map keeps its voxels
  EXPECT_EQ(automatic.stride(0.1, 0.3), 1);   // and a coarser one too
  EXPECT_DOUBLE_EQ(automatic.fieldVoxel(0.01, 0.015), 0.01);
  for (double map : {0.005, 0.01, 0.02, 0.05, 0.1})
    for (double truncation : {map, 2 * map, 4 * map})
      EXPECT_TRUE(automatic.validate(map, truncation).ok()) << map << " " << truncation;
}

}  // namespace
}  // namespace semfuse::esdf::testing
