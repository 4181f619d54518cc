// The view index on frames of known geometry: a camera at the origin looking along +z at a flat
// wall 2 m away (depth 2 everywhere), 4 cm voxels, so 32 cm leaves. Which leaves a frame saw,
// the ranking of frames by leaves seen, the per-leaf ring of 16, the depth range, clear().
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "semfuse/objects/view_index.hpp"

namespace semfuse::objects {
namespace {

constexpr double kIndexVoxel = 0.04;
constexpr double kLeaf = 8 * kIndexVoxel;
const PinholeIntrinsics kCamera{160, 120, 131.25, 131.25, 79.5, 59.5};

cv::Mat wall(float depth = 2.0f) { return cv::Mat(kCamera.height, kCamera.width, CV_32FC1, cv::Scalar(depth)); }

Pose shiftedAlongX(double x) {
  Pose pose = Pose::Identity();
  pose.translation().x() = x;
  return pose;
}

// The leaf holding the world point p.
openvdb::Coord leafAt(const Eigen::Vector3d& p) {
  const Eigen::Vector3d index = p / kIndexVoxel;
  return openvdb::Coord(static_cast<int>(std::floor(index.x() + 0.5)), static_cast<int>(std::floor(index.y() + 0.5)),
                        static_cast<int>(std::floor(index.z() + 0.5))) &
         ~7;
}

TEST(ViewIndex, AFrameSawTheLeavesOfTheWallInItsViewAndNoOthers) {
  ViewIndex views(kIndexVoxel);
  views.record("cam", 7, wall(), kCamera, Pose::Identity(), 0.1f, 5.0f);
  EXPECT_EQ(views.frameCount(), 1u);
  uint32_t total = 0;
  // The wall's centre, and a point 0.5 m to the side, both within the 2 x 1.5 m the view covers.
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.0, 0.0, 2.0), Eigen::Vector3d(0.5, -0.3, 2.0)}) {
    const std::vector<FrameRef> frames = views.framesSeeing({leafAt(p)}, 16, total);
    ASSERT_EQ(frames.size(), 1u) << p.transpose();
    EXPECT_EQ(frames[0].camera_id, "cam");
    EXPECT_EQ(frames[0].seq, 7u);
    EXPECT_EQ(total, 1u);
  }
  // Behind the wall, in front of it, and beside the view: no frame.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.0, 0.0, 2.0 + 2 * kLeaf), Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(3.0, 0.0, 2.0)}) {
    EXPECT_TRUE(views.framesSeeing({leafAt(p)}, 16, total).empty()) << p.transpose();
    EXPECT_EQ(total, 0u);
  }
}

TEST(ViewIndex, FramesThatSawMoreOfTheLeavesComeFirstThenNewerOnes) {
  ViewIndex views(kIndexVoxel);
  // Frame 1 sees x in [-1, 1] of the wall, frame 2 the same shifted 1.5 m right, frame 3 as 1.
  views.record("a", 1, wall(), kCamera, shiftedAlongX(0.0), 0.1f, 5.0f);
  views.record("b", 2, wall(), kCamera, shiftedAlongX(1.5), 0.1f, 5.0f);
  views.record("a", 3, wall(), kCamera, shiftedAlongX(0.0), 0.1f, 5.0f);
  // Leaves at x = -0.8, 0 and 0.8: frames 1 and 3 saw all three, frame 2 only the one at 0.8.
  const std::vector<openvdb::Coord> leaves{leafAt({-0.8, 0.0, 2.0}), leafAt({0.0, 0.0, 2.0}), leafAt({0.8, 0.0, 2.0})};
  uint32_t total = 0;
  const std::vector<FrameRef> frames = views.framesSeeing(leaves, 16, total);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(total, 3u);
  EXPECT_EQ(frames[0].seq, 3u);  // three leaves, newest
  EXPECT_EQ(frames[1].seq, 1u);  // three leaves
  EXPECT_EQ(frames[2].seq, 2u);  // one leaf
  EXPECT_EQ(frames[2].camera_id, "b");
  // At most max_frames, the total still counts all.
  EXPECT_EQ(views.framesSeeing(leaves, 1, total).size(), 1u);
  EXPECT_EQ(total, 3u);
}

TEST(ViewIndex, ALeafRemembersItsLatestSixteenFrames) {
  ViewIndex views(kIndexVoxel);
  for (uint64_t seq = 0; seq < 20; ++seq) views.record("cam", seq, wall(), kCamera, Pose::Identity(), 0.1f, 5.0f);
  uint32_t total = 0;
  const std::vector<FrameRef> frames = views.framesSeeing({leafAt({0.0, 0.0, 2.0})}, 32, total);
  ASSERT_EQ(frames.size(), ViewIndex::kFramesPerLeaf);
  EXPECT_EQ(total, ViewIndex::kFramesPerLeaf);
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(frames[i].seq, 19 - i);  // newest first
}

TEST(ViewIndex, DepthOutsideTheRangeIsNotSeenAndClearForgetsEverything) {
  ViewIndex views(kIndexVoxel);
  const uint64_t empty = views.version();
  views.record("cam", 1, wall(2.0f), kCamera, Pose::Identity(), 0.1f, 1.5f);  // beyond max depth
  uint32_t total = 0;
  EXPECT_TRUE(views.framesSeeing({leafAt({0.0, 0.0, 2.0})}, 16, total).empty());
  views.record("cam", 2, wall(2.0f), kCamera, Pose::Identity(), 0.1f, 5.0f);
  EXPECT_EQ(views.framesSeeing({leafAt({0.0, 0.0, 2.0})}, 16, total).size(), 1u);
  const uint64_t recorded = views.version();
  EXPECT_NE(recorded, empty);
  views.clear();
  EXPECT_NE(views.version(), recorded);
  EXPECT_EQ(views.frameCount(), 0u);
  EXPECT_TRUE(views.framesSeeing({leafAt({0.0, 0.0, 2.0})}, 16, total).empty());
  EXPECT_EQ(total, 0u);
}

TEST(ViewIndex, AFrameOfTheWrongDepthTypeRecordsNothing) {
  ViewIndex views(kIndexVoxel);
  const cv::Mat millimetres(kCamera.height, kCamera.width, CV_16UC1, cv::Scalar(2000));
  views.record("cam", 1, millimetres, kCamera, Pose::Identity(), 0.1f, 5.0f);
  EXPECT_EQ(views.frameCount(), 0u);
}

}  // namespace
}  // namespace semfuse::objects
