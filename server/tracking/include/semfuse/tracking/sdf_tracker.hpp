#pragma once
// Direct alignment of a depth image to a truncated signed distance field (Bylow et al., RSS 2013;
// Canelhas et al., IROS 2013): find the camera-to-world pose T minimising
//     sum_i rho( D(T p_i) )
// over the back-projected depth points p_i, where D is the trilinearly interpolated TSDF (zero on
// the surface, so a correctly posed point reads 0). Gauss-Newton on se(3) with left-multiplied
// increments, coarse-to-fine over a depth pyramid, robust weights, TBB-parallel normal equations.
#include <cstddef>
#include <string>

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
  kNoValidDepth,   // the image has no usable reading (all 0 / NaN / out of range)
  kTooFewInliers,  // little of the image agrees with the map (new territory, or wrong pose)
  kHighResidual,   // points agree poorly on average
  kDegenerate,     // the geometry does not constrain all six degrees of freedom
  kDiverged,       // the solution moved implausibly far from the starting guess
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
  double hessian_rcond = 0.0;  // min / max eigenvalue
  int iterations = 0;          // Gauss-Newton iterations over all levels
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

  // Aligns depth (CV_32FC1 metres, 0/NaN invalid) to the field starting from guess. An error for
  // malformed input; otherwise an Alignment, with lost_reason set when its quality is too low (its
  // pose is then the best estimate but should not be integrated).
  Result<Alignment> align(const cv::Mat& depth, const PinholeIntrinsics& intrinsics, const SdfField& field,
                          const Pose& guess);

 private:
  TrackingQuality assess(const NormalEquations& system) const;
  LostReason judge(const TrackingQuality& quality, float truncation, const Pose& guess, const Pose& result) const;

  TrackerParams params_;
  DepthPyramid pyramid_;
};

}  // namespace semfuse::tracking
