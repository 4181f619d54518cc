#include "semfuse/tracking/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {

namespace {
Status checkPair(const std::vector<Pose>& estimate, const std::vector<Pose>& reference, std::size_t min) {
  if (estimate.size() != reference.size())
    return makeError("trajectories differ in length: " + std::to_string(estimate.size()) + " estimated vs " +
                     std::to_string(reference.size()) + " reference poses");
  if (estimate.size() < min) return makeError("need at least " + std::to_string(min) + " poses");
  return Status::Ok();
}
}  // namespace

Result<AbsoluteTrajectoryError> absoluteTrajectoryError(const std::vector<Pose>& estimate,
                                                        const std::vector<Pose>& reference, bool align) {
  if (Status status = checkPair(estimate, reference, align ? 3 : 1); !status) return makeError(status.error());
  const auto n = static_cast<Eigen::Index>(estimate.size());
  Eigen::Matrix3Xd est(3, n), ref(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    est.col(i) = estimate[static_cast<std::size_t>(i)].translation();
    ref.col(i) = reference[static_cast<std::size_t>(i)].translation();
  }
  AbsoluteTrajectoryError out;
  if (align) out.alignment = Pose(Eigen::umeyama(est, ref, /*with_scaling=*/false));
  double sum_sq = 0.0, sum = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double e = (out.alignment * Eigen::Vector3d(est.col(i)) - ref.col(i)).norm();
    sum_sq += e * e;
    sum += e;
    out.max_m = std::max(out.max_m, e);
  }
  out.rmse_m = std::sqrt(sum_sq / static_cast<double>(n));
  out.mean_m = sum / static_cast<double>(n);
  return out;
}

Result<RelativePoseError> relativePoseError(const std::vector<Pose>& estimate, const std::vector<Pose>& reference) {
  if (Status status = checkPair(estimate, reference, 2); !status) return makeError(status.error());
  RelativePoseError out;
  double t_sq = 0.0, r_sq = 0.0;
  const std::size_t steps = estimate.size() - 1;
  for (std::size_t i = 0; i < steps; ++i) {
    const Pose ref_motion = reference[i].inverse() * reference[i + 1];
    const Pose est_motion = estimate[i].inverse() * estimate[i + 1];
    const Pose error = ref_motion.inverse() * est_motion;
    const double t = error.translation().norm();
    const double r = rotationAngle(error.linear()) * 180.0 / M_PI;
    t_sq += t * t;
    r_sq += r * r;
    if (t > out.translation_max_m) {
      out.translation_max_m = t;
      out.translation_max_frame = i;
    }
    out.rotation_max_deg = std::max(out.rotation_max_deg, r);
  }
  out.translation_rmse_m = std::sqrt(t_sq / static_cast<double>(steps));
  out.rotation_rmse_deg = std::sqrt(r_sq / static_cast<double>(steps));
  return out;
}

double pathLength(const std::vector<Pose>& trajectory) {
  double length = 0.0;
  for (std::size_t i = 1; i < trajectory.size(); ++i)
    length += (trajectory[i].translation() - trajectory[i - 1].translation()).norm();
  return length;
}

}  // namespace semfuse::tracking
