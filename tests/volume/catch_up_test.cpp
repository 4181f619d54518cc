// LabeledVolume::catchUpWith: a copy of the map brought up to date from the leaves changed since
// it was taken must equal a fresh copy, grid by grid and voxel by voxel (geometry, colour, the
// bayes rule's label candidates, instances, observed free space), with the same revisions.
#include <gtest/gtest.h>

#include "grid_compare.hpp"

#include "semfuse/volume/free_space.hpp"
#include "semfuse/volume/instance_integration.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::volume {
namespace {

using semfuse::testing::expectSameGrid;

const PinholeIntrinsics kRoomCamera{160, 120, 131.25, 131.25, 79.5, 59.5};

VolumeParams roomParams() {
  VolumeParams params;
  params.voxel_size = 0.02;
  params.truncation = 0.08;
  params.integrate_color = true;
  params.label_rule = LabelRule::kBayes;
  params.label_classes = 8;
  return params;
}

// A camera at (x, 0, 0) looking along +z at a wall `depth` away, with a box-shaped bump in the
// middle of the image labelled 3 (instance 7), the rest labelled 1, coloured by column.
struct View {
  cv::Mat depth, color, labels, instances;
  Pose pose = Pose::Identity();
};
View viewAt(double x, float depth) {
  View v;
  v.depth = cv::Mat(kRoomCamera.height, kRoomCamera.width, CV_32FC1, cv::Scalar(depth));
  v.depth(cv::Rect(60, 40, 40, 40)).setTo(depth - 0.3f);
  v.color = cv::Mat(kRoomCamera.height, kRoomCamera.width, CV_8UC3);
  for (int c = 0; c < kRoomCamera.width; ++c) v.color.col(c).setTo(cv::Scalar(c, 255 - c, 128));
  v.labels = cv::Mat(kRoomCamera.height, kRoomCamera.width, CV_16UC1, cv::Scalar(1));
  v.labels(cv::Rect(60, 40, 40, 40)).setTo(3);
  v.instances = cv::Mat(kRoomCamera.height, kRoomCamera.width, CV_16UC1, cv::Scalar(0));
  v.instances(cv::Rect(60, 40, 40, 40)).setTo(7);
  v.pose.translation() = Eigen::Vector3d(x, 0.0, 0.0);
  return v;
}

void fuse(LabeledVolume& volume, const View& v) {
  ASSERT_TRUE(integrate(volume, v.depth, v.color, v.labels, cv::Mat(), kRoomCamera, v.pose).ok());
  ASSERT_TRUE(integrateInstances(volume, v.depth, v.labels, v.instances, kRoomCamera, v.pose).ok());
  ASSERT_TRUE(observeFreeSpace(volume, v.depth, kRoomCamera, v.pose).ok());
}

void expectSameVolume(const LabeledVolume& a, const LabeledVolume& b) {
  expectSameGrid(&a.geometryGrid(), &b.geometryGrid(), "geometry");
  expectSameGrid(a.colorGrid(), b.colorGrid(), "colour");
  expectSameGrid(a.labelSidecarGrid(), b.labelSidecarGrid(), "label candidates");
  expectSameGrid(a.instanceGrid(), b.instanceGrid(), "instances");
  expectSameGrid(a.freeSpaceGrid(), b.freeSpaceGrid(), "free space");
  EXPECT_EQ(a.revision(), b.revision());
  EXPECT_EQ(a.framesIntegrated(), b.framesIntegrated());
  EXPECT_EQ(a.nextInstanceId(), b.nextInstanceId());
  EXPECT_EQ(a.changesSince(1).leaves, b.changesSince(1).leaves);
}

TEST(CatchUp, ACopyCaughtUpEqualsAFreshCopy) {
  LabeledVolume map(roomParams());
  fuse(map, viewAt(0.0, 1.5f));
  LabeledVolume copy = map.deepCopy();
  const LabeledVolume before = map.deepCopy();
  // New surface to the side, the same surface seen again, and free space in front of both.
  fuse(map, viewAt(0.6, 1.5f));
  fuse(map, viewAt(0.1, 1.4f));
  ASSERT_GT(map.changesSince(copy.revision()).leaves.size(), 0u);
  ASSERT_LT(map.changesSince(copy.revision()).leaves.size(), map.allocatedLeaves() + 200);
  copy.catchUpWith(map);
  expectSameVolume(copy, map);
  // The map did change: the caught-up copy is not the one from before.
  EXPECT_GT(copy.allocatedLeaves(), before.allocatedLeaves());
  // Nothing changed since: catching up again changes nothing.
  copy.catchUpWith(map);
  expectSameVolume(copy, map);
}

TEST(CatchUp, AfterAClearTheCopyStartsOver) {
  LabeledVolume map(roomParams());
  fuse(map, viewAt(0.0, 1.5f));
  LabeledVolume copy = map.deepCopy();
  map.clear();
  fuse(map, viewAt(-0.5, 2.0f));
  copy.catchUpWith(map);
  expectSameVolume(copy, map);
}

}  // namespace
}  // namespace semfuse::volume
