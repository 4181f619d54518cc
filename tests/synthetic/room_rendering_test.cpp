// Rendered depth and labels of the room against distances computed by hand from its layout
// (room.cpp: floor z = 0, walls x = +-2.5 and y = +-2, table top z = 0.75 at (0.2, 0.1), ...).
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"

namespace semfuse::synthetic {
namespace {

const PinholeIntrinsics kCamera{640, 480, 525.0, 525.0, 319.5, 239.5};

// Camera looking straight down (image x = world x, image y = world -y).
Pose lookingDown(const Eigen::Vector3d& eye) {
  Pose pose = Pose::Identity();
  pose.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  pose.translation() = eye;
  return pose;
}

RenderedView render(const LabeledScene& scene, const Pose& pose) {
  auto view = renderView(scene, kCamera, pose);
  EXPECT_TRUE(view.ok()) << view.error();
  return std::move(view).value();
}

TEST(RoomRendering, FloorSeenFromAboveIsAtCameraHeightEverywhere) {
  const LabeledScene room = makeRoom();
  // Over a clear patch of floor: every floor pixel of a fronto-parallel plane has depth 1.5.
  const RenderedView view = render(room, lookingDown({-1.5, 0.0, 1.5}));
  int floor_pixels = 0;
  for (int v = 0; v < view.depth.rows; ++v)
    for (int u = 0; u < view.depth.cols; ++u)
      if (view.labels.at<uint16_t>(v, u) == labels::kFloor) {
        ++floor_pixels;
        ASSERT_NEAR(view.depth.at<float>(v, u), 1.5f, 1e-5f) << "pixel " << u << "," << v;
      }
  EXPECT_GT(floor_pixels, 640 * 480 / 2);
  EXPECT_EQ(view.labels.at<uint16_t>(240, 320), labels::kFloor);
  const cv::Vec3f n = view.normals.at<cv::Vec3f>(240, 320);
  EXPECT_NEAR(n[2], 1.0f, 1e-6f);
}

TEST(RoomRendering, TiltedViewOfFloorAndFrontalViewOfWall) {
  const LabeledScene room = makeRoom();
  // 45 degrees down onto the floor point (1.5, -1, 0) from 1.5 m up: optical-axis depth 1.5*sqrt(2).
  const RenderedView tilted = render(room, lookAt({0, -1, 1.5}, {1.5, -1, 0}));
  EXPECT_EQ(tilted.labels.at<uint16_t>(240, 320), labels::kFloor);
  EXPECT_NEAR(tilted.depth.at<float>(240, 320), 1.5 * std::sqrt(2.0), 5e-3);  // pixel centre is 0.5 px off axis
  // Facing the +x wall at x = 2.5 from x = 0, level: 2.5 m along the axis.
  const RenderedView wall = render(room, lookAt({0, -1, 1.5}, {2.5, -1, 1.5}));
  EXPECT_EQ(wall.labels.at<uint16_t>(240, 320), labels::kWall);
  EXPECT_NEAR(wall.depth.at<float>(240, 320), 2.5f, 1e-5f);
  EXPECT_NEAR(wall.depth.at<float>(100, 500), 2.5f, 1e-5f);  // frontal plane: same depth off axis
}

TEST(RoomRendering, ObjectsHaveTheirLabelsAtTheirPixels) {
  const LabeledScene room = makeRoom();
  const RenderedView view = render(room, lookingDown({0.2, 0.1, 2.0}));
  EXPECT_EQ(view.labels.at<uint16_t>(240, 320), labels::kTable);
  EXPECT_NEAR(view.depth.at<float>(240, 320), 1.25f, 1e-5f);
  // Top of the small sphere (0.45, 0.25, 0.99): camera (0.25, -0.15, 1.01) -> pixel (449.5, 161.5).
  EXPECT_EQ(view.labels.at<uint16_t>(161, 449), labels::kSphere);
  EXPECT_NEAR(view.depth.at<float>(161, 449), 1.01f, 2e-3f);
  // The cabinet's front face is at x = 2.5 - 0.44 = 2.06.
  const RenderedView cabinet = render(room, lookAt({0, 0.8, 1.0}, {2.5, 0.8, 1.0}));
  EXPECT_EQ(cabinet.labels.at<uint16_t>(240, 320), labels::kCabinet);
  EXPECT_NEAR(cabinet.depth.at<float>(240, 320), 2.06f, 1e-5f);
  // A chair seat (0.2, -0.75, 0.45) seen from above.
  const RenderedView chair = render(room, lookingDown({0.2, -0.75, 1.5}));
  EXPECT_EQ(chair.labels.at<uint16_t>(240, 320), labels::kChair);
  EXPECT_NEAR(chair.depth.at<float>(240, 320), 1.05f, 1e-5f);
}

TEST(RoomRendering, NearestSurfaceGivesDistanceAndLabel) {
  const LabeledScene room = makeRoom();
  const NearestSurface above_table = room.nearestSurface({0, 0, 1.5});
  // Closer to the small sphere than to the table top (0.75): |(0.45, 0.25, -0.63)| - 0.12.
  EXPECT_NEAR(above_table.signed_distance, std::sqrt(0.45 * 0.45 + 0.25 * 0.25 + 0.63 * 0.63) - 0.12, 1e-12);
  EXPECT_EQ(above_table.label, labels::kSphere);
  const NearestSurface near_floor = room.nearestSurface({-1.5, 0, 0.1});
  EXPECT_NEAR(near_floor.signed_distance, 0.1, 1e-12);
  EXPECT_EQ(near_floor.label, labels::kFloor);
  const NearestSurface in_cabinet = room.nearestSurface({2.28, 0.8, 0.9});
  EXPECT_NEAR(in_cabinet.signed_distance, -0.22, 1e-12);
  EXPECT_EQ(in_cabinet.label, labels::kCabinet);
}

TEST(RoomRendering, ColourIsTexturedNotFlat) {
  const LabeledScene room = makeRoom();
  const RenderedView view = render(room, lookingDown({-1.5, 0.0, 1.5}));
  cv::Scalar mean, stddev;
  cv::meanStdDev(view.color, mean, stddev, view.labels == labels::kFloor);
  EXPECT_GT(stddev[0], 10.0);   // checker tiles and noise on the floor
  EXPECT_GT(mean[0], mean[2]);  // the floor is a warm colour
}

TEST(RoomRendering, WithoutCeilingRaysUpwardSeeNothing) {
  RoomOptions options;
  options.ceiling = false;
  const RenderedView view = render(makeRoom(options), lookAt({0, 0, 1.5}, {0.01, 0, 3.0}));
  EXPECT_EQ(view.depth.at<float>(240, 320), 0.0f);
  EXPECT_EQ(view.labels.at<uint16_t>(240, 320), kUnlabeled);
  const RenderedView closed = render(makeRoom(), lookAt({0, 0, 1.5}, {0.01, 0, 3.0}));
  EXPECT_EQ(closed.labels.at<uint16_t>(240, 320), labels::kCeiling);
  EXPECT_NEAR(closed.depth.at<float>(240, 320), 1.1f, 1e-3f);
}

TEST(RoomRendering, RejectsCamerasThatAreNotCameras) {
  const LabeledScene room = makeRoom();
  PinholeIntrinsics zero_size = kCamera;
  zero_size.width = 0;
  auto bad_size = renderView(room, zero_size, Pose::Identity());
  ASSERT_FALSE(bad_size.ok());
  EXPECT_NE(bad_size.error().find("image size"), std::string::npos);
  PinholeIntrinsics nan_focal = kCamera;
  nan_focal.fx = std::nan("");
  EXPECT_FALSE(renderView(room, nan_focal, Pose::Identity()).ok());
  Pose scaled = Pose::Identity();
  scaled.linear() *= 2.0;
  auto bad_pose = renderView(room, kCamera, scaled);
  ASSERT_FALSE(bad_pose.ok());
  EXPECT_NE(bad_pose.error().find("orthonormal"), std::string::npos);
}

}  // namespace
}  // namespace semfuse::synthetic
