#include "semfuse/tracking/camera_tracking.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "semfuse/tracking/depth_pyramid.hpp"
#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {

const char* toString(TrackingStatus status) {
  switch (status) {
    case TrackingStatus::kInitialized:
      return "initialized";
    case TrackingStatus::kGivenPose:
      return "given pose";
    case TrackingStatus::kRefined:
      return "refined";
    case TrackingStatus::kTracked:
      return "tracked";
    case TrackingStatus::kLost:
      return "lost";
  }
  return "unknown";
}

namespace {

// Given poses come from files and the wire with limited precision (7-Scenes: |R^T R - I| up to
// ~2e-3): accept small deviations and use the nearest rigid transform; reject anything that is not
// a rotation at all.
constexpr double kMaxNonOrthogonality = 1e-2;

Result<Pose> rigidGivenPose(const Pose& pose) {
  if (!pose.matrix().allFinite()) return makeError("frame pose is not finite");
  const Eigen::Matrix3d r = pose.linear();
  const double deviation = (r.transpose() * r - Eigen::Matrix3d::Identity()).norm();
  if (!(deviation <= kMaxNonOrthogonality) || !(r.determinant() > 0.0))
    return makeError(
        "frame pose rotation is not orthonormal with determinant +1 (|R^T R - I| = " + std::to_string(deviation) + ")");
  return orthonormalized(pose);
}

void accept(CameraTrackState& state, const Pose& pose) {
  // Velocity only from two consecutive good frames; after a lost frame (or the first) the model
  // restarts at rest rather than extrapolating across the gap.
  state.velocity =
      (state.initialized && state.lost_in_a_row == 0) ? state.last_pose.inverse() * pose : Pose::Identity();
  state.last_pose = pose;
  state.initialized = true;
  state.lost_in_a_row = 0;
}

}  // namespace

Result<TrackedFrame> trackFrame(SdfTracker& tracker, const Frame& frame, const SdfField& field, CameraTrackState& state,
                                GivenPosePolicy policy) {
  TrackedFrame out;
  if (Status status = validateDepthImage(frame.depth, frame.intrinsics); !status) return makeError(status.error());
  std::optional<Pose> given;
  if (frame.camera_to_world) {
    Result<Pose> rigid = rigidGivenPose(*frame.camera_to_world);
    if (!rigid) return makeError(rigid.error());
    given = rigid.value();
  }

  const bool use_given = given.has_value();
  const bool refine = use_given && policy == GivenPosePolicy::kRefine;
  if (use_given && !refine) {
    out.status = TrackingStatus::kGivenPose;
    out.pose = out.guess = *given;
  } else if (!use_given && !state.initialized) {
    out.status = TrackingStatus::kInitialized;
    out.pose = out.guess = orthonormalized(state.initial_pose);
  } else {
    out.guess = use_given ? *given : orthonormalized(state.predictNext());
    Result<Alignment> aligned = tracker.align(frame.depth, frame.intrinsics, field, out.guess);
    if (!aligned) return makeError(aligned.error());
    out.quality = aligned.value().quality;
    out.lost_reason = aligned.value().lost_reason;
    if (aligned.value().ok()) {
      out.status = refine ? TrackingStatus::kRefined : TrackingStatus::kTracked;
      out.pose = aligned.value().pose;
    } else if (refine) {
      out.status = TrackingStatus::kGivenPose;  // a given pose stays usable without refinement
      out.pose = out.guess;
    } else {
      out.status = TrackingStatus::kLost;
      out.pose = state.last_pose;
    }
  }

  ++state.frames;
  if (out.status == TrackingStatus::kLost) {
    ++state.lost_total;
    ++state.lost_in_a_row;
    state.velocity = Pose::Identity();
  } else {
    accept(state, out.pose);
  }
  return out;
}

}  // namespace semfuse::tracking
