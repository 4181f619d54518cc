// The per-camera policy: first frame, given poses, refinement, constant-velocity prediction, and
// what a lost frame does to the state. Uses the exact field of the room so that only the policy
// is under test.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "analytic_field.hpp"
#include "semfuse/tracking/camera_tracking.hpp"
#include "tracking_fixtures.hpp"

namespace semfuse::tracking::testing {
namespace {

class CameraTracking : public ::testing::Test {
 protected:
  CameraTracking() : scene_(synthetic::makeRoom()), field_(scene_, 0.1f, roomInterior()) {}

  Frame frameAt(const Pose& pose, bool with_pose) const {
    const synthetic::RenderedView view = renderOrDie(scene_, pose);
    Frame frame;
    frame.camera_id = "test";
    frame.intrinsics = view.intrinsics;
    frame.depth = view.depth;
    if (with_pose) frame.camera_to_world = pose;
    return frame;
  }

  // A short smooth path: 2 cm and 0.5 degrees per frame.
  static Pose pathPose(int i) {
    Pose step = Pose::Identity();
    step.linear() = Eigen::AngleAxisd(0.5 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    step.translation() = Eigen::Vector3d(0.02, 0.0, 0.0);
    Pose pose = referencePose();
    for (int k = 0; k < i; ++k) pose = pose * step;
    return pose;
  }

  synthetic::LabeledScene scene_;
  AnalyticField field_;
  SdfTracker tracker_;
  CameraTrackState state_;
};

TEST_F(CameraTracking, FirstFrameWithoutPoseIsPlacedAtTheInitialPose) {
  state_.initial_pose = pathPose(0);
  Result<TrackedFrame> first = trackFrame(tracker_, frameAt(pathPose(0), false), field_, state_);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first.value().status, TrackingStatus::kInitialized);
  EXPECT_TRUE(first.value().shouldIntegrate());
  EXPECT_TRUE(first.value().pose.isApprox(pathPose(0)));
  EXPECT_TRUE(state_.initialized);
}

TEST_F(CameraTracking, GivenPoseIsUsedAsItIs) {
  Pose off = pathPose(0);
  off.translation().x() += 0.03;  // deliberately not the pose of the image
  Frame frame = frameAt(pathPose(0), false);
  frame.camera_to_world = off;
  Result<TrackedFrame> out = trackFrame(tracker_, frame, field_, state_, GivenPosePolicy::kUseAsIs);
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out.value().status, TrackingStatus::kGivenPose);
  EXPECT_TRUE(out.value().pose.isApprox(off));
}

TEST_F(CameraTracking, SlightlyNonRigidGivenPoseIsSnappedToTheNearestRotation) {
  // As 7-Scenes pose files are: a rotation perturbed by ~1e-3.
  Pose file_pose = pathPose(0);
  file_pose.linear() += 1e-3 * Eigen::Matrix3d::Ones();
  Frame frame = frameAt(pathPose(0), false);
  frame.camera_to_world = file_pose;
  Result<TrackedFrame> out = trackFrame(tracker_, frame, field_, state_);
  ASSERT_TRUE(out.ok()) << out.error();
  const Eigen::Matrix3d r = out.value().pose.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT(rotationErrorDeg(out.value().pose, pathPose(0)), 0.2);
}

TEST_F(CameraTracking, GivenPoseIsRefinedOnRequest) {
  Frame frame = frameAt(pathPose(0), false);
  Pose off = pathPose(0);
  off.translation() += Eigen::Vector3d(0.03, -0.02, 0.01);
  frame.camera_to_world = off;
  Result<TrackedFrame> out = trackFrame(tracker_, frame, field_, state_, GivenPosePolicy::kRefine);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().status, TrackingStatus::kRefined);
  EXPECT_LT(translationError(out.value().pose, pathPose(0)), 1e-3);
  EXPECT_TRUE(out.value().guess.isApprox(off));
}

TEST_F(CameraTracking, TracksASequenceAndLearnsTheVelocity) {
  state_.initial_pose = pathPose(0);
  for (int i = 0; i < 4; ++i) {
    Result<TrackedFrame> out = trackFrame(tracker_, frameAt(pathPose(i), false), field_, state_);
    ASSERT_TRUE(out.ok()) << out.error();
    EXPECT_TRUE(out.value().shouldIntegrate()) << "frame " << i << ": " << toString(out.value().lost_reason);
    EXPECT_LT(translationError(out.value().pose, pathPose(i)), 1e-3) << "frame " << i;
    EXPECT_LT(rotationErrorDeg(out.value().pose, pathPose(i)), 0.05) << "frame " << i;
    if (i >= 2) {
      // Constant velocity: the start guess of frame i is frame i-1 moved by the last motion, which
      // on this uniform path is already within a fraction of a millimetre of the truth.
      EXPECT_LT(translationError(out.value().guess, pathPose(i)), 1e-3) << "frame " << i;
    }
  }
  EXPECT_NEAR(state_.velocity.translation().norm(), 0.02, 1e-3);
  EXPECT_EQ(state_.frames, 4u);
  EXPECT_EQ(state_.lost_total, 0u);
}

TEST_F(CameraTracking, LostFrameKeepsTheLastGoodPoseAndResetsTheVelocity) {
  state_.initial_pose = pathPose(0);
  ASSERT_TRUE(trackFrame(tracker_, frameAt(pathPose(0), false), field_, state_).ok());
  ASSERT_TRUE(trackFrame(tracker_, frameAt(pathPose(1), false), field_, state_).ok());
  const Pose last_good = state_.last_pose;

  Frame blind = frameAt(pathPose(2), false);
  blind.depth.setTo(std::numeric_limits<float>::quiet_NaN());
  Result<TrackedFrame> lost = trackFrame(tracker_, blind, field_, state_);
  ASSERT_TRUE(lost.ok()) << lost.error();
  EXPECT_EQ(lost.value().status, TrackingStatus::kLost);
  EXPECT_EQ(lost.value().lost_reason, LostReason::kNoValidDepth);
  EXPECT_FALSE(lost.value().shouldIntegrate());
  EXPECT_TRUE(lost.value().pose.isApprox(last_good));
  EXPECT_TRUE(state_.velocity.isApprox(Pose::Identity()));
  EXPECT_EQ(state_.lost_in_a_row, 1u);
  EXPECT_EQ(state_.lost_total, 1u);

  // The next frame is tried from the last good pose (two steps away: 4 cm, 1 degree) and found.
  Result<TrackedFrame> back = trackFrame(tracker_, frameAt(pathPose(3), false), field_, state_);
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back.value().status, TrackingStatus::kTracked);
  EXPECT_TRUE(back.value().guess.isApprox(last_good));
  EXPECT_LT(translationError(back.value().pose, pathPose(3)), 1e-3);
  EXPECT_EQ(state_.lost_in_a_row, 0u);
}

TEST_F(CameraTracking, MalformedFramesAreErrorsAndLeaveTheStateAlone) {
  state_.initial_pose = pathPose(0);
  ASSERT_TRUE(trackFrame(tracker_, frameAt(pathPose(0), false), field_, state_).ok());
  const CameraTrackState before = state_;

  Frame empty = frameAt(pathPose(1), false);
  empty.depth = cv::Mat();
  Result<TrackedFrame> a = trackFrame(tracker_, empty, field_, state_);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("empty"), std::string::npos);

  Frame skewed = frameAt(pathPose(1), false);
  Pose not_rigid = pathPose(1);
  not_rigid.linear() *= 1.1;
  skewed.camera_to_world = not_rigid;
  Result<TrackedFrame> b = trackFrame(tracker_, skewed, field_, state_);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("orthonormal"), std::string::npos);

  Frame wrong_size = frameAt(pathPose(1), false);
  wrong_size.intrinsics.width = 320;
  EXPECT_FALSE(trackFrame(tracker_, wrong_size, field_, state_).ok());

  EXPECT_EQ(state_.frames, before.frames);
  EXPECT_TRUE(state_.last_pose.isApprox(before.last_pose));
}

}  // namespace
}  // namespace semfuse::tracking::testing
