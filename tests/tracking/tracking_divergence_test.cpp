// Jumps far beyond the basin of convergence: the synthetic orbit taken in 20 frames moves the
// camera ~50 cm and ~18 degrees between frames, while a 5 cm band pulls in a few centimetres.
// The alignment then settles on some wrong pose; the tracker must report it lost instead of letting
// it be integrated (which would corrupt the map and every later frame), and may integrate a frame
// only at its true pose.
#include <vector>

#include <gtest/gtest.h>

#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/tracking/tracker.hpp"
#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/integrator.hpp"
#include "tracking_fixtures.hpp"

namespace semfuse::tracking::testing {
namespace {

// The benchmark's map: 1 cm voxels, 5 cm truncation.
volume::VolumeParams benchMapParams() { return geometryMapParams(0.01, 0.05); }

TEST(TrackingDivergence, JumpsBeyondTheBasinAreLostNotAccepted) {
  synthetic::SequenceConfig config;
  config.trajectory.frame_count = 20;
  const synthetic::SyntheticSequence sequence(config);
  const double step = (sequence.pose(1).translation() - sequence.pose(0).translation()).norm();
  ASSERT_GT(step, 0.4) << "the test needs jumps far beyond the 5 cm band";

  volume::LabeledVolume map(benchMapParams());
  const VolumeField field(map);
  TrackerConfig tracker_config;
  tracker_config.initial_pose = sequence.pose(0);
  Tracker tracker(tracker_config);
  int lost = 0;
  for (int i = 0; i < sequence.frameCount(); ++i) {
    Result<Frame> frame = sequence.frame(i, /*with_pose=*/false);
    ASSERT_TRUE(frame.ok()) << frame.error();
    Result<TrackedFrame> tracked = tracker.track(frame.value(), field, map.framesIntegrated() == 0);
    ASSERT_TRUE(tracked.ok()) << tracked.error();
    const TrackedFrame& t = tracked.value();
    if (!t.shouldIntegrate()) {
      ++lost;
      continue;
    }
    // Exact depth: an accepted pose is right to millimetres, anything else was accepted wrongly.
    EXPECT_LT(translationError(t.pose, sequence.pose(i)), 0.01)
        << "frame " << i << " accepted " << translationError(t.pose, sequence.pose(i)) << " m from the truth"
        << " (inliers " << t.quality.inlier_ratio << ", agreement " << t.quality.observed_agreement << ")";
    EXPECT_LT(rotationErrorDeg(t.pose, sequence.pose(i)), 0.5) << "frame " << i;
    ASSERT_TRUE(volume::integrate(map, frame.value().depth, cv::Mat(), frame.value().intrinsics, t.pose).ok());
    tracker.integrated(frame.value(), t);
  }
  // Every frame after the first jumps from the last good pose by more than the basin: tracking
  // cannot follow, and only a frame that a keyframe of the map places again can be integrated.
  EXPECT_GE(lost, sequence.frameCount() - 3);
}

}  // namespace
}  // namespace semfuse::tracking::testing
