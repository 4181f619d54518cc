// The tracker's per-camera policy: first frame, given poses, refinement, constant-velocity
// prediction, what a lost frame does to the camera, and a second camera without a pose. Uses the
// exact field of the room so that only the policy is under test.
#include <atomic>
#include <cmath>
#include <limits>
#include <thread>

#include <gtest/gtest.h>

#include "analytic_field.hpp"
#include "semfuse/tracking/tracker.hpp"
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

  // A tracker whose world frame starts at the path's first pose.
  static TrackerConfig startingAtThePath(GivenPosePolicy policy = GivenPosePolicy::kUseAsIs) {
    TrackerConfig config;
    config.initial_pose = pathPose(0);
    config.given_pose = policy;
    return config;
  }

  Result<TrackedFrame> track(Tracker& tracker, const Frame& frame, bool map_empty = false) {
    return tracker.track(frame, field_, map_empty);
  }

  CameraTrackingSummary summary(const Tracker& tracker, const std::string& camera = "test") {
    return tracker.cameras().at(camera);
  }

  synthetic::LabeledScene scene_;
  AnalyticField field_;
};

TEST_F(CameraTracking, FirstFrameWithoutPoseOnAnEmptyMapIsPlacedAtTheInitialPose) {
  Tracker tracker(startingAtThePath());
  Result<TrackedFrame> first = track(tracker, frameAt(pathPose(0), false), /*map_empty=*/true);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_EQ(first.value().status, TrackingStatus::kInitialized);
  EXPECT_TRUE(first.value().shouldIntegrate());
  EXPECT_TRUE(first.value().pose.isApprox(pathPose(0)));
  EXPECT_FALSE(summary(tracker).lost);
}

TEST_F(CameraTracking, GivenPoseIsUsedAsItIs) {
  Tracker tracker(startingAtThePath());
  Pose off = pathPose(0);
  off.translation().x() += 0.03;  // deliberately not the pose of the image
  Frame frame = frameAt(pathPose(0), false);
  frame.camera_to_world = off;
  Result<TrackedFrame> out = track(tracker, frame);
  ASSERT_TRUE(out.ok());
  EXPECT_EQ(out.value().status, TrackingStatus::kGivenPose);
  EXPECT_TRUE(out.value().pose.isApprox(off));
}

TEST_F(CameraTracking, AFrameTooSmallToTrackIsStillIntegratedAtItsOwnPose) {
  // 16x12 cannot hold the tracker's pyramid; a frame that carries its pose does not need one.
  Tracker tracker(startingAtThePath());
  Frame tiny;
  tiny.camera_id = "tiny";
  tiny.intrinsics = {16, 12, 10.0, 10.0, 8.0, 6.0};
  tiny.depth = cv::Mat(12, 16, CV_32FC1, cv::Scalar(1.5f));
  tiny.camera_to_world = pathPose(0);
  Result<TrackedFrame> out = track(tracker, tiny);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().status, TrackingStatus::kGivenPose);
  // Without its pose there is nothing to track it with: a clear error, not a guess.
  tiny.camera_to_world.reset();
  Result<TrackedFrame> unposed = track(tracker, tiny);
  ASSERT_FALSE(unposed.ok());
  EXPECT_NE(unposed.error().find("too small"), std::string::npos) << unposed.error();
}

TEST_F(CameraTracking, SlightlyNonRigidGivenPoseIsSnappedToTheNearestRotation) {
  Tracker tracker(startingAtThePath());
  // As 7-Scenes pose files are: a rotation perturbed by ~1e-4.
  Pose file_pose = pathPose(0);
  file_pose.linear() += 1e-4 * Eigen::Matrix3d::Ones();
  Frame frame = frameAt(pathPose(0), false);
  frame.camera_to_world = file_pose;
  Result<TrackedFrame> out = track(tracker, frame);
  ASSERT_TRUE(out.ok()) << out.error();
  const Eigen::Matrix3d r = out.value().pose.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT(rotationErrorDeg(out.value().pose, pathPose(0)), 0.05);
}

TEST_F(CameraTracking, GivenPoseIsRefinedOnRequest) {
  Tracker tracker(startingAtThePath(GivenPosePolicy::kRefine));
  Frame frame = frameAt(pathPose(0), false);
  Pose off = pathPose(0);
  off.translation() += Eigen::Vector3d(0.03, -0.02, 0.01);
  frame.camera_to_world = off;
  Result<TrackedFrame> out = track(tracker, frame);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().status, TrackingStatus::kRefined);
  EXPECT_LT(translationError(out.value().pose, pathPose(0)), 1e-3);
  EXPECT_TRUE(out.value().guess.isApprox(off));
}

TEST_F(CameraTracking, TracksASequenceFromTheMotionPrediction) {
  Tracker tracker(startingAtThePath());
  for (int i = 0; i < 4; ++i) {
    Result<TrackedFrame> out = track(tracker, frameAt(pathPose(i), false), /*map_empty=*/i == 0);
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
  EXPECT_EQ(summary(tracker).frames, 4u);
  EXPECT_EQ(summary(tracker).lost_total, 0u);
}

TEST_F(CameraTracking, BlindFrameIsLostAndTheNextOneIsTriedFromTheLastGoodPose) {
  Tracker tracker(startingAtThePath());
  ASSERT_TRUE(track(tracker, frameAt(pathPose(0), false), true).ok());
  Result<TrackedFrame> second = track(tracker, frameAt(pathPose(1), false));
  ASSERT_TRUE(second.ok());
  const Pose last_good = second.value().pose;

  Frame blind = frameAt(pathPose(2), false);
  blind.depth.setTo(std::numeric_limits<float>::quiet_NaN());
  Result<TrackedFrame> lost = track(tracker, blind);
  ASSERT_TRUE(lost.ok()) << lost.error();
  EXPECT_EQ(lost.value().status, TrackingStatus::kLost);
  EXPECT_EQ(lost.value().lost_reason, LostReason::kNoValidDepth);
  EXPECT_FALSE(lost.value().shouldIntegrate());
  EXPECT_TRUE(summary(tracker).lost);
  EXPECT_EQ(summary(tracker).frames_since_lost, 1u);
  EXPECT_EQ(summary(tracker).lost_total, 1u);

  // The next frame (two steps away: 4 cm, 1 degree) is found again.
  Result<TrackedFrame> back = track(tracker, frameAt(pathPose(3), false));
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE(back.value().shouldIntegrate()) << toString(back.value().lost_reason);
  EXPECT_LT(translationError(back.value().pose, pathPose(3)), 1e-3);
  EXPECT_LT(translationError(last_good, pathPose(1)), 1e-3);
  EXPECT_FALSE(summary(tracker).lost);
  EXPECT_EQ(summary(tracker).frames_since_lost, 0u);
}

// The server's field locks the map in beginReading() and unlocks it in endReading(): the tracker
// must sample only between the two, on the thread that opened the reading, and close every
// reading it opens; a frame with a pose of its own reads nothing.
class ReadingCountingField final : public SdfField {
 public:
  explicit ReadingCountingField(const SdfField& field) : field_(field) {}
  float truncation() const override { return field_.truncation(); }
  std::unique_ptr<SdfSampler> makeSampler() const override {
    if (open_ == 0 || std::this_thread::get_id() != reader_) ++outside_;
    return std::make_unique<Sampler>(field_.makeSampler(), *this);
  }
  void beginReading() const override {
    if (open_++ == 0) reader_ = std::this_thread::get_id();
    ++readings_;
  }
  void endReading() const override { --open_; }

  int readings() const { return readings_; }
  int open() const { return open_; }
  int outside() const { return outside_; }  // samplers made or used outside a reading or its thread

 private:
  class Sampler final : public SdfSampler {
   public:
    Sampler(std::unique_ptr<SdfSampler> inner, const ReadingCountingField& field)
        : inner_(std::move(inner)), field_(field) {}
    bool sample(const Eigen::Vector3f& p, SdfSample& out) override {
      check();
      return inner_->sample(p, out);
    }
    bool sampleWithIntensity(const Eigen::Vector3f& p, SdfSample& out) override {
      check();
      return inner_->sampleWithIntensity(p, out);
    }

   private:
    void check() const {
      if (field_.open_ == 0 || std::this_thread::get_id() != field_.reader_) ++field_.outside_;
    }
    std::unique_ptr<SdfSampler> inner_;
    const ReadingCountingField& field_;
  };

  const SdfField& field_;
  mutable std::atomic<int> open_{0};
  mutable std::atomic<int> readings_{0};
  mutable std::atomic<int> outside_{0};
  mutable std::thread::id reader_;
};

TEST_F(CameraTracking, ReadsTheFieldOnlyInsideReadingsOnItsOwnThread) {
  const ReadingCountingField counting(field_);
  Tracker tracker(startingAtThePath());
  ASSERT_TRUE(tracker.track(frameAt(pathPose(0), false), counting, /*map_empty=*/true).ok());
  EXPECT_EQ(counting.readings(), 0);  // placed at the initial pose: nothing to align to

  for (int i = 1; i <= 3; ++i) {
    const int before = counting.readings();
    Result<TrackedFrame> out = tracker.track(frameAt(pathPose(i), false), counting, false);
    ASSERT_TRUE(out.ok()) << out.error();
    EXPECT_TRUE(out.value().shouldIntegrate()) << i;
    EXPECT_GE(counting.readings(), before + 1) << i;
  }
  // A blind frame (no points) and the relocalisation of the next one.
  Frame blind = frameAt(pathPose(4), false);
  blind.depth.setTo(std::numeric_limits<float>::quiet_NaN());
  ASSERT_TRUE(tracker.track(blind, counting, false).ok());
  ASSERT_TRUE(tracker.track(frameAt(pathPose(5), false), counting, false).ok());

  const int before_given = counting.readings();
  ASSERT_TRUE(tracker.track(frameAt(pathPose(6), true), counting, false).ok());
  EXPECT_EQ(counting.readings(), before_given);  // its own pose, used as it is

  EXPECT_GE(counting.readings(), 4);
  EXPECT_EQ(counting.open(), 0);
  EXPECT_EQ(counting.outside(), 0);
}

TEST_F(CameraTracking, MalformedFramesAreErrorsAndLeaveTheCameraAlone) {
  Tracker tracker(startingAtThePath());
  ASSERT_TRUE(track(tracker, frameAt(pathPose(0), false), true).ok());
  const CameraTrackingSummary before = summary(tracker);

  Frame empty = frameAt(pathPose(1), false);
  empty.depth = cv::Mat();
  Result<TrackedFrame> a = track(tracker, empty);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("empty"), std::string::npos);

  Frame skewed = frameAt(pathPose(1), false);
  Pose not_rigid = pathPose(1);
  not_rigid.linear() *= 1.1;
  skewed.camera_to_world = not_rigid;
  Result<TrackedFrame> b = track(tracker, skewed);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().find("orthonormal"), std::string::npos) << b.error();

  Frame wrong_size = frameAt(pathPose(1), false);
  wrong_size.intrinsics.width = 320;
  EXPECT_FALSE(track(tracker, wrong_size).ok());

  EXPECT_EQ(summary(tracker).frames, before.frames);
  EXPECT_EQ(summary(tracker).last_status, before.last_status);
}

TEST_F(CameraTracking, SecondCameraWithoutPoseIsNotPlacedBlindly) {
  Tracker tracker(startingAtThePath());
  ASSERT_TRUE(track(tracker, frameAt(pathPose(0), false), true).ok());
  Frame other = frameAt(pathPose(1), false);
  other.camera_id = "other";
  Result<TrackedFrame> out = track(tracker, other);
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().status, TrackingStatus::kLost);
  EXPECT_EQ(out.value().lost_reason, LostReason::kNotPlaced);
  EXPECT_TRUE(summary(tracker, "other").lost);
}

}  // namespace
}  // namespace semfuse::tracking::testing
