// What the tracker does when the camera leaves the path it can follow: a kidnap, a covered sensor,
// a view of one plane, dropped frames, a second camera that joins without a pose. Everything is
// measured against the synthetic room's exact poses: a frame is integrated only at a pose within
// a centimetre and a degree of the truth, and the camera is found again within a few frames of
// seeing a place a keyframe shows.
#include <cmath>
#include <limits>
#include <string>

#include <gtest/gtest.h>

#include "analytic_field.hpp"
#include "semfuse/tracking/tracker.hpp"
#include "tracking_fixtures.hpp"

namespace semfuse::tracking::testing {
namespace {

class Relocalisation : public ::testing::Test {
 protected:
  Relocalisation() : scene_(synthetic::makeRoom()), field_(scene_, 0.1f, roomInterior()) {
    TrackerConfig config;
    config.initial_pose = pathPose(0);
    tracker_ = std::make_unique<Tracker>(config);
  }

  Frame frameAt(const Pose& pose, const std::string& camera = "cam") const {
    const synthetic::RenderedView view = renderOrDie(scene_, pose);
    Frame frame;
    frame.camera_id = camera;
    frame.intrinsics = view.intrinsics;
    frame.depth = view.depth;
    frame.color = view.color;
    return frame;
  }

  // Tracks one frame as the server does (integrated frames may become keyframes) and checks the
  // one rule that holds in every case: nothing is integrated at a wrong pose.
  TrackedFrame step(const Frame& frame, const Pose& truth, bool map_empty = false) {
    Result<TrackedFrame> out = tracker_->track(frame, field_, map_empty);
    EXPECT_TRUE(out.ok()) << out.error();
    if (!out.ok()) return {};
    if (out.value().shouldIntegrate()) {
      EXPECT_LT(translationError(out.value().pose, truth), 0.01) << "integrated at a wrong pose";
      EXPECT_LT(rotationErrorDeg(out.value().pose, truth), 1.0) << "integrated at a wrong pose";
      tracker_->integrated(frame, out.value());
    }
    return out.value();
  }

  TrackedFrame stepAt(int i, bool map_empty = false) { return step(frameAt(pathPose(i)), pathPose(i), map_empty); }

  // Tracks the path 0..last (the first frame defines the world frame).
  void followPath(int last) {
    for (int i = 0; i <= last; ++i) ASSERT_TRUE(stepAt(i, i == 0).shouldIntegrate()) << "frame " << i;
  }

  CameraTrackingSummary summary(const std::string& camera = "cam") const { return tracker_->camera(camera); }

  synthetic::LabeledScene scene_;
  AnalyticField field_;
  std::unique_ptr<Tracker> tracker_;
};

TEST_F(Relocalisation, AKidnappedCameraIsNeverIntegratedAtAGuessAndIsFoundWhereAKeyframeWas) {
  followPath(20);
  ASSERT_GE(tracker_->keyframes(), 2u);
  // Carried off to the other end of the room, looking at what no keyframe shows: no pose can be
  // verified there, so nothing is integrated (step() would fail on a wrong pose).
  const Pose elsewhere = synthetic::lookAt(Eigen::Vector3d(-1.8, 1.5, 1.2), Eigen::Vector3d(2.0, 1.8, 0.5));
  for (int i = 0; i < 3; ++i) {
    const TrackedFrame away = step(frameAt(elsewhere), elsewhere);
    EXPECT_FALSE(away.shouldIntegrate()) << "frame " << i << " away: " << toString(away.status);
  }
  EXPECT_TRUE(summary().lost);
  EXPECT_EQ(summary().relocalisations, 0u);
  // Brought back to where the path started (4 m away, facing the other way): a keyframe
  // proposes the pose, the next frame confirms it.
  int frames_to_comeback = 0;
  for (int i = 0; i < 10; ++i) {
    ++frames_to_comeback;
    if (stepAt(0).shouldIntegrate()) break;
  }
  EXPECT_LE(frames_to_comeback, 3);
  EXPECT_EQ(summary().relocalisations, 1u);
  EXPECT_FALSE(summary().lost);
  // And it tracks on from there.
  for (int i = 1; i <= 5; ++i) EXPECT_EQ(stepAt(i).status, TrackingStatus::kTracked) << "frame " << i;
}

TEST_F(Relocalisation, ACoveredSensorLosesTheCameraUntilItSeesAgain) {
  followPath(10);
  // Eight frames without depth while the camera moves on by 16 cm and 4 degrees.
  for (int i = 11; i <= 18; ++i) {
    Frame covered = frameAt(pathPose(i));
    covered.depth.setTo(0.0f);
    const TrackedFrame out = step(covered, pathPose(i));
    EXPECT_EQ(out.status, TrackingStatus::kLost);
    EXPECT_EQ(out.lost_reason, LostReason::kNoValidDepth);
  }
  EXPECT_TRUE(summary().lost);
  EXPECT_EQ(summary().frames_since_lost, 8u);
  int frames_to_comeback = 0;
  for (int i = 19; i < 29; ++i) {
    ++frames_to_comeback;
    if (stepAt(i).shouldIntegrate()) break;
  }
  EXPECT_LE(frames_to_comeback, 3);
  EXPECT_FALSE(summary().lost);
  EXPECT_EQ(summary().frames_since_lost, 0u);
}

TEST_F(Relocalisation, AViewOfOnePlaneIsNotIntegratedAtAPoseThePlaneLeavesFree) {
  followPath(10);
  // Only the floor: the depth fixes height, roll and pitch, nothing along the floor.
  for (int i = 11; i <= 16; ++i) {
    Frame floor_only = frameAt(pathPose(i));
    const Pose& pose = pathPose(i);
    const PinholeIntrinsics& k = floor_only.intrinsics;
    for (int v = 0; v < floor_only.depth.rows; ++v)
      for (int u = 0; u < floor_only.depth.cols; ++u) {
        float& z = floor_only.depth.at<float>(v, u);
        const Eigen::Vector3d p = pose * Eigen::Vector3d((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z);
        if (!(z > 0.0f) || p.z() > 0.02) z = 0.0f;
      }
    step(floor_only, pose);  // integrated or not, never at a wrong pose
  }
  int frames_to_comeback = 0;
  for (int i = 17; i < 27; ++i) {
    ++frames_to_comeback;
    if (stepAt(i).shouldIntegrate()) break;
  }
  EXPECT_LE(frames_to_comeback, 3);
}

TEST_F(Relocalisation, DroppedFramesAreBridgedByTheImageAlignment) {
  ASSERT_TRUE(stepAt(0, true).shouldIntegrate());
  // Every fourth frame: 8 cm and 2 degrees between frames.
  for (int i = 4; i <= 40; i += 4) EXPECT_EQ(stepAt(i).status, TrackingStatus::kTracked) << "frame " << i;
  EXPECT_EQ(summary().lost_total, 0u);
}

TEST_F(Relocalisation, ASecondCameraWithoutPoseIsPlacedByAKeyframeAndConfirmedByItsNextFrame) {
  followPath(10);
  const TrackedFrame first = step(frameAt(pathPose(3), "other"), pathPose(3));
  EXPECT_EQ(first.status, TrackingStatus::kLost);
  EXPECT_EQ(first.lost_reason, LostReason::kUnconfirmed);
  const TrackedFrame second = step(frameAt(pathPose(4), "other"), pathPose(4));
  EXPECT_EQ(second.status, TrackingStatus::kRelocalised);
  EXPECT_EQ(summary("other").relocalisations, 1u);
  EXPECT_EQ(stepAt(11).status, TrackingStatus::kTracked);  // the first camera is unaffected
  EXPECT_EQ(step(frameAt(pathPose(5), "other"), pathPose(5)).status, TrackingStatus::kTracked);
}

}  // namespace
}  // namespace semfuse::tracking::testing
