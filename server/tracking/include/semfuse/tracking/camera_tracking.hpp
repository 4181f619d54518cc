#pragma once
// Per-camera tracking policy (DESIGN.md §4): what pose a frame is integrated at, given what the
// frame carries and how the camera has moved so far.
//  - a frame with a pose: that pose as it is, or refined by alignment (GivenPosePolicy::kRefine);
//  - a frame without one: aligned to the map from a constant-velocity prediction;
//  - the camera's first frame without a pose: the state's initial pose (identity by default: the
//    first frame of a map defines the world frame).
// A LOST frame leaves the state at the last good pose (velocity reset), so the next frame is tried
// from there.
#include <cstdint>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/tracking/sdf_field.hpp"
#include "semfuse/tracking/sdf_tracker.hpp"

namespace semfuse::tracking {

enum class GivenPosePolicy {
  kUseAsIs,  // trust the pose the frame carries
  kRefine,   // use it as the starting guess of an alignment (kept as is if the alignment fails)
};

enum class TrackingStatus {
  kInitialized,  // camera's first frame: placed at the initial pose, integrate it
  kGivenPose,    // the frame's own pose was used
  kRefined,      // the frame's own pose, refined by alignment
  kTracked,      // aligned to the map from the motion prediction
  kLost,         // alignment not trusted: do not integrate
};
const char* toString(TrackingStatus status);

// Everything the tracker remembers about one camera between its frames.
struct CameraTrackState {
  bool initialized = false;
  Pose initial_pose = Pose::Identity();  // used for the first frame if it carries no pose
  Pose last_pose = Pose::Identity();     // last pose a frame was integrated at
  // Camera motion between the last two good frames, in the camera frame (T_prev^-1 T_last): the
  // constant-velocity model predicts the next pose as last_pose * velocity.
  Pose velocity = Pose::Identity();
  uint64_t frames = 0;
  uint64_t lost_total = 0;
  uint64_t lost_in_a_row = 0;

  Pose predictNext() const { return last_pose * velocity; }
};

struct TrackedFrame {
  TrackingStatus status = TrackingStatus::kLost;
  LostReason lost_reason = LostReason::kNone;  // set when status is kLost (or a refinement failed)
  Pose pose = Pose::Identity();                // pose to integrate at (last good pose if lost)
  Pose guess = Pose::Identity();               // where the alignment started
  TrackingQuality quality;                     // of the alignment, when one ran
  bool shouldIntegrate() const { return status != TrackingStatus::kLost; }
};

// Decides the pose of `frame` and updates `state`. Errors for malformed frames (empty or wrongly
// typed depth, size not matching the intrinsics, non-finite or non-rigid given pose) leave the
// state untouched.
Result<TrackedFrame> trackFrame(SdfTracker& tracker, const Frame& frame, const SdfField& field, CameraTrackState& state,
                                GivenPosePolicy policy = GivenPosePolicy::kUseAsIs);

}  // namespace semfuse::tracking
