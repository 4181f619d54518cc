#pragma once
// Trajectory error measures of the TUM RGB-D benchmark (Sturm et al., IROS 2012), used by the
// tracking benchmark and tests: absolute trajectory error (ATE) with and without a rigid
// Horn/Umeyama alignment, and the relative pose error (RPE) between consecutive frames.
#include <cstddef>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::tracking {

struct AbsoluteTrajectoryError {
  double rmse_m = 0.0;
  double mean_m = 0.0;
  double max_m = 0.0;
  Pose alignment = Pose::Identity();  // applied to the estimate (identity when not aligned)
};

struct RelativePoseError {
  double translation_rmse_m = 0.0;  // per frame step
  double translation_max_m = 0.0;
  double rotation_rmse_deg = 0.0;
  double rotation_max_deg = 0.0;
  std::size_t translation_max_frame = 0;  // the step from this frame to the next is the worst
};

// Camera-centre errors of `estimate` against `reference` (same length, index = frame). With
// align, the estimate is first moved by the rigid transform (no scale) that best fits its camera
// centres to the reference ones in the least-squares sense (Umeyama, PAMI 1991).
Result<AbsoluteTrajectoryError> absoluteTrajectoryError(const std::vector<Pose>& estimate,
                                                        const std::vector<Pose>& reference, bool align);

// Error of each estimated frame-to-frame motion against the reference motion.
Result<RelativePoseError> relativePoseError(const std::vector<Pose>& estimate, const std::vector<Pose>& reference);

// Length of the path travelled by the camera centre.
double pathLength(const std::vector<Pose>& trajectory);

}  // namespace semfuse::tracking
