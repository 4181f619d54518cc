// Changed-block tracking (LabeledVolume::changesSince) and observed free space (observeFreeSpace):
// which leaves each write stamps, what a clear, a copy and a loaded map report, and which voxels
// a frame looking at a wall sees as empty.
#include <algorithm>
#include <filesystem>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "semfuse/volume/free_space.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::volume {
namespace {

const PinholeIntrinsics kWallCamera{160, 120, 131.25, 131.25, 79.5, 59.5};

VolumeParams wallParams() {
  VolumeParams params;
  params.voxel_size = 0.02;
  params.truncation = 0.08;
  params.integrate_color = false;
  params.label_rule = LabelRule::kEvidence;
  return params;
}

// A camera at the origin looking along +z at a wall `depth` metres away, moved along x.
Pose cameraAt(double x) {
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return pose;
}
cv::Mat wall(float depth) { return cv::Mat(kWallCamera.height, kWallCamera.width, CV_32FC1, cv::Scalar(depth)); }

using Origins = std::set<std::tuple<int, int, int>>;
Origins originsOf(const std::vector<openvdb::Coord>& leaves) {
  Origins out;
  for (const auto& c : leaves) out.insert({c.x(), c.y(), c.z()});
  return out;
}
Origins geometryLeaves(const LabeledVolume& volume) {
  Origins out;
  for (auto leaf = volume.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf)
    out.insert({leaf->origin().x(), leaf->origin().y(), leaf->origin().z()});
  return out;
}

TEST(ChangedLeaves, EveryWriteStampsTheLeavesItTouched) {
  LabeledVolume volume(wallParams());
  EXPECT_EQ(volume.revision(), 0u);
  EXPECT_FALSE(volume.changesSince(0).all);
  EXPECT_TRUE(volume.changesSince(0).leaves.empty());

  auto first = integrate(volume, wall(1.5f), cv::Mat(), kWallCamera, cameraAt(0.0));
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(volume.revision(), 1u);
  const auto after_first = volume.changesSince(0);
  EXPECT_FALSE(after_first.all);
  EXPECT_EQ(after_first.revision, 1u);
  EXPECT_EQ(after_first.leaves.size(), first.value().leaves_touched);
  EXPECT_EQ(originsOf(after_first.leaves), geometryLeaves(volume));

  // A second view 1 m to the side: only the leaves it touched are new since revision 1.
  auto second = integrate(volume, wall(1.5f), cv::Mat(), kWallCamera, cameraAt(1.0));
  ASSERT_TRUE(second.ok());
  const auto after_second = volume.changesSince(1);
  EXPECT_EQ(after_second.leaves.size(), second.value().leaves_touched);
  EXPECT_LT(after_second.leaves.size(), geometryLeaves(volume).size());
  EXPECT_TRUE(volume.changesSince(2).leaves.empty());

  // A late label pass stamps the leaves whose labels it may change, and allocates none.
  const cv::Mat labels(kWallCamera.height, kWallCamera.width, CV_16UC1, cv::Scalar(4));
  const std::size_t leaves = volume.allocatedLeaves();
  ASSERT_TRUE(integrateLabels(volume, wall(1.5f), labels, cv::Mat(), kWallCamera, cameraAt(0.0)).ok());
  EXPECT_EQ(volume.allocatedLeaves(), leaves);
  EXPECT_EQ(volume.changesSince(2).leaves.size(), first.value().leaves_touched);

  // A bad frame changes nothing, not even the revision.
  EXPECT_FALSE(integrate(volume, wall(1.5f), cv::Mat(), PinholeIntrinsics{10, 10, 0, 0, 0, 0}, cameraAt(0)).ok());
  EXPECT_EQ(volume.revision(), 3u);

  // A copy carries the stamps.
  const LabeledVolume copy = volume.deepCopy();
  EXPECT_EQ(copy.revision(), volume.revision());
  EXPECT_EQ(originsOf(copy.changesSince(1).leaves), originsOf(volume.changesSince(1).leaves));
}

TEST(ChangedLeaves, ClearAndLoadChangeEverything) {
  LabeledVolume volume(wallParams());
  ASSERT_TRUE(integrate(volume, wall(1.5f), cv::Mat(), kWallCamera, cameraAt(0.0)).ok());
  const uint64_t before = volume.revision();
  volume.clear();
  EXPECT_GT(volume.revision(), before);
  const auto cleared = volume.changesSince(before);
  EXPECT_TRUE(cleared.all);  // whoever was up to date before the clear starts again
  EXPECT_TRUE(cleared.leaves.empty());
  EXPECT_FALSE(volume.changesSince(volume.revision()).all);

  ASSERT_TRUE(integrate(volume, wall(1.5f), cv::Mat(), kWallCamera, cameraAt(0.0)).ok());
  ASSERT_TRUE(observeFreeSpace(volume, wall(1.5f), kWallCamera, cameraAt(0.0)).ok());
  const auto folder = std::filesystem::temp_directory_path() / ("semfuse_changed_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  ASSERT_TRUE(saveMap(volume, LabelLegend{}, folder / "map.vdb").ok());
  auto loaded = loadMap(folder / "map.vdb");
  std::filesystem::remove_all(folder);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  LabeledVolume& map = loaded.value().volume;
  // A consumer starting from nothing rebuilds from every leaf: geometry and observed free space.
  const auto all = map.changesSince(0);
  EXPECT_TRUE(all.all);
  const Origins listed = originsOf(all.leaves);
  for (const auto& leaf : geometryLeaves(map)) EXPECT_TRUE(listed.count(leaf));
  EXPECT_GT(listed.size(), geometryLeaves(map).size());
  // Free space survives the file.
  ASSERT_NE(map.freeSpaceGrid(), nullptr);
  EXPECT_EQ(map.freeSpaceGrid()->activeVoxelCount(), volume.freeSpaceGrid()->activeVoxelCount());
  // A map that replaces another continues its revisions.
  map.continueRevisionsFrom(volume.revision());
  EXPECT_GT(map.revision(), volume.revision());
  EXPECT_TRUE(map.changesSince(volume.revision()).all);
}

TEST(FreeSpace, AFrameSeesTheSpaceInFrontOfItsBandAndNothingElse) {
  LabeledVolume volume(wallParams());
  const float depth = 1.5f;
  auto stats = observeFreeSpace(volume, wall(depth), kWallCamera, cameraAt(0.0));
  ASSERT_TRUE(stats.ok()) << stats.error();
  EXPECT_GT(stats.value().new_free_leaves, 0u);
  const double h = volume.voxelSize(), truncation = volume.params().truncation;
  std::size_t free_voxels = 0;
  for (auto it = volume.freeSpaceGrid()->tree().cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (auto ijk = box.begin(); ijk; ++ijk) {
      const Eigen::Vector3d p = volume.indexToWorld(*ijk);
      ++free_voxels;
      // In front of the camera, inside its view, nearer than the wall minus the truncation.
      ASSERT_GT(p.z(), 0.0);
      ASSERT_LT(p.z(), depth - truncation) << p.transpose();
      ASSERT_LE(std::abs(kWallCamera.fx * p.x() / p.z()), kWallCamera.width / 2.0 + 1);
      ASSERT_LE(std::abs(kWallCamera.fy * p.y() / p.z()), kWallCamera.height / 2.0 + 1);
    }
  }
  // Most of the frustum in front of the band is seen: its volume is about
  // (depth - truncation)^3 * (w / f) * (h / f) / 3.
  const double frustum = std::pow(depth - truncation, 3) * (kWallCamera.width / kWallCamera.fx) *
                         (kWallCamera.height / kWallCamera.fy) / 3.0 / (h * h * h);
  EXPECT_GT(free_voxels, 0.8 * frustum);
  EXPECT_LT(free_voxels, 1.05 * frustum);
  // Behind the wall, and beside the frustum, nothing.
  EXPECT_FALSE(volume.observedFree(volume.worldToIndex({0.0, 0.0, depth + 0.2})));
  EXPECT_FALSE(volume.observedFree(volume.worldToIndex({0.0, 0.0, depth - 0.5 * truncation})));
  EXPECT_FALSE(volume.observedFree(volume.worldToIndex({2.0, 0.0, 0.5})));
  EXPECT_TRUE(volume.observedFree(volume.worldToIndex({0.0, 0.0, 1.0})));
  // The same frame again adds nothing; the regions were stamped once.
  const uint64_t revision = volume.revision();
  auto again = observeFreeSpace(volume, wall(depth), kWallCamera, cameraAt(0.0));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.value().new_free_leaves + again.value().new_free_voxels, 0u);
  EXPECT_EQ(volume.revision(), revision);
}

TEST(FreeSpace, InvalidDepthSeesNothingAndBadInputIsRefused) {
  LabeledVolume volume(wallParams());
  auto none = observeFreeSpace(volume, wall(0.0f), kWallCamera, cameraAt(0.0));
  ASSERT_TRUE(none.ok());
  EXPECT_EQ(none.value().new_free_leaves + none.value().new_free_voxels, 0u);
  EXPECT_FALSE(observeFreeSpace(volume, cv::Mat(3, 3, CV_32FC1, cv::Scalar(1.0f)), kWallCamera, cameraAt(0.0)).ok());
  Pose sheared = cameraAt(0.0);
  sheared.linear()(0, 1) = 0.5;
  EXPECT_FALSE(observeFreeSpace(volume, wall(1.0f), kWallCamera, sheared).ok());
  EXPECT_EQ(volume.revision(), 0u);
  EXPECT_FALSE(observeFreeSpace(volume, wall(1.0f), kWallCamera, cameraAt(0.0), 0).ok());
}

// With a sample stride, a voxel whose coordinates are all multiples of it is free exactly when it
// is free without one; any other voxel is free only inside a wholly free leaf (a tile).
TEST(FreeSpace, ASampleStrideMarksTheSameVoxelsAtItsSamplesAndNoOthers) {
  constexpr int kStride = 3;  // not a divisor of 8: samples fall at every offset in some leaf
  LabeledVolume full(wallParams()), sampled(wallParams());
  for (double x : {0.0, 0.3}) {
    ASSERT_TRUE(observeFreeSpace(full, wall(1.5f), kWallCamera, cameraAt(x)).ok());
    ASSERT_TRUE(observeFreeSpace(sampled, wall(1.5f), kWallCamera, cameraAt(x), kStride).ok());
  }
  const openvdb::CoordBBox box = full.freeSpaceGrid()->evalActiveVoxelBoundingBox();
  ASSERT_GT(box.volume(), 100000u);
  const auto sample = [](int c) { return ((c % kStride) + kStride) % kStride == 0; };
  std::size_t samples = 0, samples_differ = 0, others_free = 0, others_outside_tiles = 0;
  const auto& tree = sampled.freeSpaceGrid()->tree();
  for (auto it = box.begin(); it; ++it) {
    const openvdb::Coord c = *it;
    const bool free = sampled.observedFree(c);
    if (sample(c.x()) && sample(c.y()) && sample(c.z())) {
      ++samples;
      samples_differ += free != full.observedFree(c);
    } else if (free) {
      ++others_free;
      others_outside_tiles += tree.probeConstLeaf(c) != nullptr;
    }
  }
  EXPECT_GT(samples, 3000u);
  EXPECT_EQ(samples_differ, 0u);
  EXPECT_GT(others_free, 0u);  // the wholly free leaves near the camera
  EXPECT_EQ(others_outside_tiles, 0u);
}

}  // namespace
}  // namespace semfuse::volume
