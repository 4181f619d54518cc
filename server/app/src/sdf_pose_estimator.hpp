#pragma once
// The server's PoseEstimator: direct SDF alignment (semfuse::tracking) against the map.
#include "mapper.hpp"
#include "semfuse/tracking/sdf_tracker.hpp"
#include "semfuse/tracking/volume_field.hpp"

namespace semfuse::server {

class SdfPoseEstimator final : public PoseEstimator {
 public:
  explicit SdfPoseEstimator(tracking::TrackerParams params = {}) : tracker_(params) {}

  Estimate estimate(const volume::LabeledVolume& volume, const Frame& frame, const Pose& guess) override {
    Estimate estimate;
    tracking::VolumeField field(volume);
    auto alignment = tracker_.align(frame.depth, frame.intrinsics, field, guess);
    if (!alignment.ok()) {
      estimate.failure = alignment.error();
      return estimate;
    }
    const auto& a = alignment.value();
    estimate.ok = a.ok();
    estimate.camera_to_world = a.pose;
    estimate.inlier_ratio = static_cast<float>(a.quality.inlier_ratio);
    estimate.residual = static_cast<float>(a.quality.rms_residual_m);
    estimate.iterations = static_cast<uint32_t>(a.quality.iterations);
    if (!a.ok()) estimate.failure = tracking::toString(a.lost_reason);
    return estimate;
  }

 private:
  tracking::SdfTracker tracker_;  // fusion thread only: keeps its buffers between frames
};

}  // namespace semfuse::server
