#pragma once
// Direct alignment of a depth image to a truncated signed distance field (Bylow et al., RSS 2013;
// Canelhas et al., IROS 2013): find the camera-to-world pose T minimising
//     sum_i rho( D(T p_i) )
// over the back-projected depth points p_i, where D is the trilinearly interpolated TSDF (zero on
// the surface, so a correctly posed point reads 0). Gauss-Newton on se(3) with left-multiplied
// increments, coarse-to-fine over a depth pyramid, robust weights, TBB-parallel normal equations.
#include <cstddef>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/tracking/depth_pyramid.hpp"
#include "semfuse/tracking/normal_equations.hpp"
#include "semfuse/tracking/sdf_field.hpp"
#include "semfuse/tracking/tracker_params.hpp"

namespace semfuse::tracking {

// Why an alignment was not trusted.
enum class LostReason {
  kNone,
  kNoValidDepth,      // the image has no usable reading (all 0 / NaN / out of range)
  kTooFewInliers,     // little of the image agrees with the map (new territory, or wrong pose)
  kHighResidual,      // points agree poorly on average
  kDegenerate,        // depth and colour leave some directions free; every other test passed
  kDiverged,          // the solution moved implausibly far from the starting guess
  kNotPlaced,         // a camera without a pose that no keyframe of the map has placed yet
  kDisagreesWithMap,  // passes the aligner's tests, but far fewer points agree with the map than before
  kUnconfirmed,       // relocalised, waiting for the next frame to confirm the pose
};
const char* toString(LostReason reason);

struct TrackingQuality {
  std::size_t points = 0;  // finest-level points evaluated at the final pose
  std::size_t inliers = 0;
  double inlier_ratio = 0.0;
  std::size_t observed = 0;             // points that landed where the map was observed, at any |D|
  double observed_agreement = 0.0;      // inliers / observed
  double rms_residual_m = 0.0;          // RMS of D over the inliers
  double hessian_min_eigenvalue = 0.0;  // of the depth-scaled Hessian, per point
  double hessian_max_eigenvalue = 0.0;
  double hessian_rcond = 0.0;    // min / max eigenvalue (of the depth term alone)
  int constrained_dofs = 6;      // directions depth and colour together constrain (the rest: the start's)
  std::size_t color_points = 0;  // points with a photometric residual at the final pose
  double color_rms = 0.0;        // RMS of the intensity residual over them (0..1)
  int iterations = 0;            // Gauss-Newton iterations over all levels
  int start = 0;                 // which of the starting poses the alignment continued from
};

struct Alignment {
  Pose pose = Pose::Identity();
  TrackingQuality quality;
  LostReason lost_reason = LostReason::kNone;
  bool ok() const { return lost_reason == LostReason::kNone; }
};

// Holds the pyramid and point buffers between calls, so one tracker per fusion thread (any number
// of cameras, one at a time) allocates nothing per frame once it has seen a frame of each size.
class SdfTracker {
 public:
  explicit SdfTracker(TrackerParams params = {});
  // Fails on invalid parameters; the constructor keeps them as they are and align() reports it.
  static Status validate(const TrackerParams& params);

  const TrackerParams& params() const { return params_; }

  // Takes the frame to align: depth (CV_32FC1 metres, 0/NaN invalid) and, optionally, colour
  // (CV_8UC3 RGB, same size) for the photometric term. Fails on malformed input.
  Status setFrame(const cv::Mat& depth, const cv::Mat& color, const PinholeIntrinsics& intrinsics);
  // The frame's depth (and intensity) pyramid, as setFrame() built it.
  const DepthPyramid& pyramid() const { return pyramid_; }

  // Aligns the frame given to setFrame() to the field. Every start is tried on the coarsest level;
  // the alignment goes on from the one that fits best. An error for malformed input; otherwise an
  // Alignment, with lost_reason set when its quality is too low (its pose is then the best
  // estimate but should not be integrated).
  Result<Alignment> align(const SdfField& field, const std::vector<Pose>& starts);

  // setFrame() and align() in one call.
  Result<Alignment> align(const cv::Mat& depth, const cv::Mat& color, const PinholeIntrinsics& intrinsics,
                          const SdfField& field, const std::vector<Pose>& starts) {
    if (Status status = setFrame(depth, color, intrinsics); !status) return makeError(status.error());
    return align(field, starts);
  }
  Result<Alignment> align(const cv::Mat& depth, const PinholeIntrinsics& intrinsics, const SdfField& field,
                          const Pose& guess) {
    return align(depth, cv::Mat(), intrinsics, field, {guess});
  }

 private:
  TrackingQuality assess(const NormalEquations& depth_system, const NormalEquations& color_system) const;
  LostReason judge(const TrackingQuality& quality, float truncation, const Pose& guess, const Pose& result) const;

  TrackerParams params_;
  DepthPyramid pyramid_;
  bool frame_ready_ = false;
};

}  // namespace semfuse::tracking
