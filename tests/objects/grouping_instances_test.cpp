// Panoptic instances in the grouping: two instances a segmentation saw apart are two objects
// whatever the geometry; two never seen apart (a face of a box first seen alone, the rest of the
// box later) join where the geometry joins them. The surface is one flat square of one label,
// its left half one instance and its right half another.
#include <gtest/gtest.h>

#include <vector>

#include "semfuse/objects/grouping.hpp"
#include "semfuse/volume/instance_evidence.hpp"

namespace semfuse::objects {
namespace {

constexpr double kSquareVoxel = 0.01;
constexpr int kSquareSide = 40;  // voxels: each half 0.08 m^2, an object of its own

SurfaceVoxels squareOfTwoInstances() {
  std::vector<SurfaceVoxel> voxels;
  for (int x = 0; x < kSquareSide; ++x)
    for (int y = 0; y < kSquareSide; ++y) {
      SurfaceVoxel v;
      v.ijk = openvdb::Coord(x, y, 0);
      v.normal = Eigen::Vector3f::UnitZ();
      v.area_m2 = static_cast<float>(kSquareVoxel * kSquareVoxel);
      v.label = 5;
      v.instance = x < kSquareSide / 2 ? 1 : 2;
      voxels.push_back(v);
    }
  return SurfaceVoxels(kSquareVoxel, std::move(voxels));
}

std::vector<Group> objectsOf(const Grouping& grouping) {
  std::vector<Group> out;
  for (const Group& group : grouping.groups)
    if (!group.fragment) out.push_back(group);
  return out;
}

TEST(GroupingInstances, InstancesSeenApartAreTwoObjectsOnOneFlatSurface) {
  SurfaceVoxels surface = squareOfTwoInstances();
  surface.setInstancePairsSeenApart({volume::instancePairKey(1, 2)});
  const std::vector<Group> objects = objectsOf(groupSurface(surface, ObjectParams{}));
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].voxel_count, kSquareSide * kSquareSide / 2u);
  EXPECT_EQ(objects[1].voxel_count, kSquareSide * kSquareSide / 2u);
  EXPECT_NE(objects[0].instance, objects[1].instance);
}

TEST(GroupingInstances, InstancesNeverSeenApartJoinWhereTheGeometryJoinsThem) {
  const SurfaceVoxels surface = squareOfTwoInstances();  // no pair seen apart
  const std::vector<Group> objects = objectsOf(groupSurface(surface, ObjectParams{}));
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(objects[0].voxel_count, static_cast<uint64_t>(kSquareSide * kSquareSide));
}

TEST(GroupingInstances, APairSeenApartKeepsOnlyThatPairApart) {
  SurfaceVoxels surface = squareOfTwoInstances();
  surface.setInstancePairsSeenApart({volume::instancePairKey(1, 3), volume::instancePairKey(2, 4)});
  EXPECT_FALSE(surface.instancesSeenApart(1, 2));
  EXPECT_TRUE(surface.instancesSeenApart(3, 1));
  EXPECT_EQ(objectsOf(groupSurface(surface, ObjectParams{})).size(), 1u);
}

}  // namespace
}  // namespace semfuse::objects
