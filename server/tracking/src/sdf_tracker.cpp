#include "semfuse/tracking/sdf_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_reduce.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "semfuse/tracking/se3.hpp"

namespace semfuse::tracking {

const char* toString(LostReason reason) {
  switch (reason) {
    case LostReason::kNone:
      return "none";
    case LostReason::kNoValidDepth:
      return "no valid depth";
    case LostReason::kTooFewInliers:
      return "too few inliers";
    case LostReason::kHighResidual:
      return "high residual";
    case LostReason::kDegenerate:
      return "degenerate geometry";
    case LostReason::kDiverged:
      return "diverged";
  }
  return "unknown";
}

namespace {

using Samplers = tbb::enumerable_thread_specific<std::unique_ptr<SdfSampler>>;

// Thresholds of one pass, in metres (fractions of the truncation resolved once per frame).
struct ResidualModel {
  RobustLoss loss;
  float scale;
  float band;
  float inlier;

  float weight(float r) const {
    const float a = std::abs(r);
    if (loss == RobustLoss::kHuber) return a <= scale ? 1.0f : scale / a;
    const float u = r / scale;
    return 1.0f / (1.0f + u * u);
  }
};

// One parallel pass: residuals D(T p) and Jacobians over all points of a level. For a point moved
// by a left increment, d/dxi D(exp(xi) q) at xi = 0 is grad^T [I | -[q]x] = (grad, q x grad).
NormalEquations accumulate(const std::vector<Eigen::Vector3f>& points, Samplers& samplers, const ResidualModel& model,
                           const Pose& pose) {
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const Eigen::Vector3f translation = pose.translation().cast<float>();
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), 512), NormalEquations{},
      [&](const tbb::blocked_range<std::size_t>& range, NormalEquations system) {
        SdfSampler& sampler = *samplers.local();
        SdfSample sample;
        Eigen::Matrix<float, 6, 1> jacobian;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const Eigen::Vector3f q = rotation * points[i] + translation;
          if (!sampler.sample(q, sample)) continue;  // unobserved: no information
          ++system.observed;
          const float r = sample.distance;
          if (!(std::abs(r) < model.band)) continue;  // flat truncated region (or NaN)
          if (sample.gradient.squaredNorm() < 1e-12f) continue;
          jacobian.head<3>() = sample.gradient;
          jacobian.tail<3>() = q.cross(sample.gradient);
          system.add(jacobian, r, model.weight(r));
          if (std::abs(r) < model.inlier) {
            ++system.inliers;
            system.inlier_sq_sum += static_cast<double>(r) * r;
          }
        }
        return system;
      },
      [](NormalEquations a, const NormalEquations& b) {
        a.join(b);
        return a;
      });
}

}  // namespace

SdfTracker::SdfTracker(TrackerParams params) : params_(std::move(params)) {}

Status SdfTracker::validate(const TrackerParams& p) {
  if (std::any_of(p.max_iterations.begin(), p.max_iterations.end(), [](int n) { return n < 0; }))
    return makeError("max_iterations must not be negative");
  if (!(p.robust_scale > 0.0f) || !(p.band_fraction > 0.0f) || !(p.band_fraction <= 1.0f) ||
      !(p.inlier_fraction > 0.0f))
    return makeError("robust_scale, band_fraction (<= 1) and inlier_fraction must be > 0");
  if (!(p.max_correction_fraction > 0.0f) || !(p.max_correction_rad > 0.0))
    return makeError("max_correction_fraction and max_correction_rad must be > 0");
  if (!(p.damping >= 0.0) || !(p.convergence_norm >= 0.0))
    return makeError("damping and convergence_norm must not be negative");
  return Status::Ok();
}

Result<Alignment> SdfTracker::align(const cv::Mat& depth, const PinholeIntrinsics& intrinsics, const SdfField& field,
                                    const Pose& guess) {
  if (Status status = validate(params_); !status) return makeError("tracker parameters: " + status.error());
  if (!guess.matrix().allFinite()) return makeError("starting pose is not finite");
  const float truncation = field.truncation();
  if (!(truncation > 0.0f) || !std::isfinite(truncation)) return makeError("field truncation must be finite and > 0");
  if (Status status = pyramid_.build(depth, intrinsics, params_.pyramid); !status) return makeError(status.error());

  Alignment result;
  result.pose = guess;
  if (pyramid_.points(0).empty()) {
    result.lost_reason = LostReason::kNoValidDepth;
    return result;
  }

  const ResidualModel model{params_.loss, params_.robust_scale * truncation, params_.band_fraction * truncation,
                            params_.inlier_fraction * truncation};
  // One sampler per worker thread for the whole frame: the field does not change while aligning.
  Samplers samplers([&field] { return field.makeSampler(); });

  Pose pose = guess;
  int iterations = 0;
  for (int level = pyramid_.levels() - 1; level >= 0; --level) {
    const std::vector<Eigen::Vector3f>& points = pyramid_.points(level);
    for (int it = 0; it < params_.max_iterations.at(static_cast<std::size_t>(level)); ++it) {
      const NormalEquations system = accumulate(points, samplers, model, pose);
      if (system.residuals < 6) break;  // nothing to solve for at this level
      Matrix6d hessian = system.hessian();
      hessian.diagonal().array() += params_.damping * hessian.diagonal().mean();
      const Vector6d step = hessian.ldlt().solve(-system.gradient());
      if (!step.allFinite()) break;
      pose = expSE3(step) * pose;
      ++iterations;
      if (step.norm() < params_.convergence_norm) break;
    }
  }

  pose = orthonormalized(pose);  // ~20 float-precision updates leave it slightly off SO(3)
  result.pose = pose;
  result.quality = assess(accumulate(pyramid_.points(0), samplers, model, pose));
  result.quality.iterations = iterations;
  result.lost_reason = judge(result.quality, truncation, guess, pose);
  return result;
}

TrackingQuality SdfTracker::assess(const NormalEquations& system) const {
  TrackingQuality q;
  q.points = pyramid_.points(0).size();
  q.inliers = system.inliers;
  q.inlier_ratio = q.points > 0 ? static_cast<double>(q.inliers) / static_cast<double>(q.points) : 0.0;
  q.observed = system.observed;
  q.observed_agreement = q.observed > 0 ? static_cast<double>(q.inliers) / static_cast<double>(q.observed) : 0.0;
  q.rms_residual_m = q.inliers > 0 ? std::sqrt(system.inlier_sq_sum / static_cast<double>(q.inliers)) : 0.0;
  if (system.residuals == 0) return q;
  // Rotational columns of J are (q x grad), metres times the translational ones; scaling them by
  // 1 / mean depth makes the eigenvalues of both blocks comparable, so the reciprocal condition
  // measures missing constraints rather than the units.
  const double length = std::max(pyramid_.meanDepth(), 0.1);
  Eigen::Matrix<double, 6, 1> scale;
  scale << 1.0, 1.0, 1.0, 1.0 / length, 1.0 / length, 1.0 / length;
  const Matrix6d scaled =
      scale.asDiagonal() * system.hessian() * scale.asDiagonal() / static_cast<double>(system.residuals);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(scaled, Eigen::EigenvaluesOnly);
  q.hessian_min_eigenvalue = eigen.eigenvalues()(0);
  q.hessian_max_eigenvalue = eigen.eigenvalues()(5);
  q.hessian_rcond =
      q.hessian_max_eigenvalue > 0.0 ? std::max(q.hessian_min_eigenvalue, 0.0) / q.hessian_max_eigenvalue : 0.0;
  return q;
}

LostReason SdfTracker::judge(const TrackingQuality& q, float truncation, const Pose& guess, const Pose& result) const {
  if (q.inliers < params_.min_inliers || q.inlier_ratio < params_.min_inlier_ratio) return LostReason::kTooFewInliers;
  if (q.hessian_rcond < params_.min_hessian_rcond) return LostReason::kDegenerate;
  if (q.rms_residual_m > params_.max_rms_fraction * truncation) return LostReason::kHighResidual;
  // In the camera frame, so the translation is how far the camera centre moved (a world-frame
  // difference would grow with the distance from the world origin).
  const Pose correction = guess.inverse() * result;
  if (correction.translation().norm() > params_.max_correction_fraction * truncation ||
      rotationAngle(correction.linear()) > params_.max_correction_rad)
    return LostReason::kDiverged;
  return LostReason::kNone;
}

}  // namespace semfuse::tracking
