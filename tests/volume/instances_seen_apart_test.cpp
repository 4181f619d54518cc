// Instances seen apart: one segmentation's segments are recorded as pairs of different objects,
// each pair once, and a frame cut into more segments than kMaxSegmentsSeenApart records the pairs
// of its largest ones only.
#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/instance_integration.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::volume {
namespace {

// A plane 1 m in front of the camera with geometry and labels, for instance maps to land on.
struct SeenApartPlane {
  PinholeIntrinsics k = testing::smallCamera();
  Pose pose = testing::lookAt({0, 0, 0}, {0, 0, 1});
  cv::Mat depth = testing::renderPlane(k, pose, {0, 0, -1}, -1.0);
  cv::Mat labels = cv::Mat(k.height, k.width, CV_16UC1, cv::Scalar(4));
  LabeledVolume volume{VolumeParams{}};

  SeenApartPlane() {
    const cv::Mat confidence(k.height, k.width, CV_32FC1, cv::Scalar(0.8));
    const cv::Mat color(k.height, k.width, CV_8UC3, cv::Scalar(0, 0, 0));
    EXPECT_TRUE(integrate(volume, depth, color, labels, confidence, k, pose).ok());
  }
  // The image cut into a grid of cells, each cell one segment.
  cv::Mat grid(int columns, int rows) const {
    cv::Mat instances(k.height, k.width, CV_16UC1);
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u)
        instances.at<uint16_t>(v, u) =
            static_cast<uint16_t>(1 + (u * columns / k.width) + columns * (v * rows / k.height));
    return instances;
  }
};

TEST(InstancesSeenApart, AFramesSegmentsArePairsOfDifferentObjectsEachOnce) {
  SeenApartPlane plane;
  const cv::Mat instances = plane.grid(3, 1);
  for (int frame = 0; frame < 2; ++frame) {  // the second frame matches the same three instances
    auto fused = integrateInstances(plane.volume, plane.depth, plane.labels, instances, plane.k, plane.pose);
    ASSERT_TRUE(fused.ok()) << fused.error();
    EXPECT_EQ(fused.value().created, frame == 0 ? 3u : 0u);
  }
  EXPECT_EQ(plane.volume.instancePairsSeenApart().size(), 3u);
  EXPECT_TRUE(plane.volume.instancesSeenApart(1, 2));
  EXPECT_TRUE(plane.volume.instancesSeenApart(3, 1));
  EXPECT_FALSE(plane.volume.instancesSeenApart(1, 4));
}

TEST(InstancesSeenApart, AFrameOfManySegmentsRecordsTheLargestOnesPairsOnly) {
  SeenApartPlane plane;
  const cv::Mat instances = plane.grid(16, 10);  // 160 segments of about 50 voxels
  auto fused = integrateInstances(plane.volume, plane.depth, plane.labels, instances, plane.k, plane.pose);
  ASSERT_TRUE(fused.ok()) << fused.error();
  ASSERT_GT(fused.value().created, kMaxSegmentsSeenApart);
  EXPECT_EQ(plane.volume.instancePairsSeenApart().size(), kMaxSegmentsSeenApart * (kMaxSegmentsSeenApart - 1) / 2);
}

}  // namespace
}  // namespace semfuse::volume
