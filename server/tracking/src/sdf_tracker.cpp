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
    case LostReason::kNotPlaced:
      return "not placed in the map yet";
    case LostReason::kDisagreesWithMap:
      return "disagrees with the map";
    case LostReason::kUnconfirmed:
      return "relocalised, not confirmed yet";
  }
  return "unknown";
}

namespace {

using Samplers = tbb::enumerable_thread_specific<std::unique_ptr<SdfSampler>>;

// Thresholds of one pass, in metres (fractions of the truncation resolved once per frame), and
// the photometric term's scale.
struct ResidualModel {
  RobustLoss loss;
  float scale;
  float band;
  float inlier;
  float color_scale;                                  // Huber scale of intensity residuals; 0 = no photometric term
  float noise_base, noise_quadratic, noise_multiple;  // depth noise model of the inlier test

  float weight(float r) const {
    const float a = std::abs(r);
    if (loss == RobustLoss::kHuber) return a <= scale ? 1.0f : scale / a;
    const float u = r / scale;
    return 1.0f / (1.0f + u * u);
  }
  float colorWeight(float r) const {
    const float a = std::abs(r);
    return a <= color_scale ? 1.0f : color_scale / a;
  }
};

// The normal equations of one pass: the depth term and the photometric term apart, so that the
// depth's own conditioning can be judged and the colour weighted when they are combined.
struct PassSystems {
  NormalEquations depth;
  NormalEquations color;
  void join(const PassSystems& other) {
    depth.join(other.depth);
    color.join(other.color);
  }
};

// One parallel pass over all points of a level. For a point moved by a left increment,
// d/dxi F(exp(xi) q) at xi = 0 is grad^T [I | -[q]x] = (grad, q x grad) for any field F: the
// TSDF D (residual D(T p), zero on the surface) and the fused intensity C (residual C(T p) - I(p)).
PassSystems accumulate(const std::vector<Eigen::Vector3f>& points, const std::vector<float>& intensities,
                       Samplers& samplers, const ResidualModel& model, const Pose& pose) {
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const Eigen::Vector3f translation = pose.translation().cast<float>();
  const bool photometric = model.color_scale > 0.0f && intensities.size() == points.size();
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, points.size(), 512), PassSystems{},
      [&](const tbb::blocked_range<std::size_t>& range, PassSystems systems) {
        SdfSampler& sampler = *samplers.local();
        SdfSample sample;
        Eigen::Matrix<float, 6, 1> jacobian;
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const Eigen::Vector3f q = rotation * points[i] + translation;
          const bool valid = photometric ? sampler.sampleWithIntensity(q, sample) : sampler.sample(q, sample);
          if (!valid) continue;  // unobserved: no information
          ++systems.depth.observed;
          const float r = sample.distance;
          if (!(std::abs(r) < model.band)) continue;  // flat truncated region (or NaN)
          if (sample.gradient.squaredNorm() < 1e-12f) continue;
          jacobian.head<3>() = sample.gradient;
          jacobian.tail<3>() = q.cross(sample.gradient);
          systems.depth.add(jacobian, r, model.weight(r));
          // An inlier lies within what the sensor's noise at that range explains, and at least
          // within inlier_fraction of the truncation.
          const float z = points[i].z();
          const float sigma = model.noise_base + model.noise_quadratic * (z - 0.4f) * (z - 0.4f);
          const bool inlier = std::abs(r) < std::max(model.inlier, model.noise_multiple * sigma);
          if (inlier) {
            ++systems.depth.inliers;
            systems.depth.inlier_sq_sum += static_cast<double>(r) * r;
          }
          // Colour only where the point is near the surface: elsewhere the fused colour belongs to
          // another surface (or to free space, where it was never meant to be compared).
          if (!photometric || !inlier || !sample.has_intensity) continue;
          const float rc = sample.intensity - intensities[i];
          if (!std::isfinite(rc)) continue;
          jacobian.head<3>() = sample.intensity_gradient;
          jacobian.tail<3>() = q.cross(sample.intensity_gradient);
          systems.color.add(jacobian, rc, model.colorWeight(rc));
          ++systems.color.inliers;
          systems.color.inlier_sq_sum += static_cast<double>(rc) * rc;
        }
        return systems;
      },
      [](PassSystems a, const PassSystems& b) {
        a.join(b);
        return a;
      });
}

}  // namespace

SdfTracker::SdfTracker(TrackerParams params) : params_(params) {}

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

Status SdfTracker::setFrame(const cv::Mat& depth, const cv::Mat& color, const PinholeIntrinsics& intrinsics) {
  frame_ready_ = false;
  if (Status status = validate(params_); !status) return makeError("tracker parameters: " + status.error());
  if (Status status = pyramid_.build(depth, color, intrinsics, params_.pyramid); !status) return status;
  frame_ready_ = true;
  return Status::Ok();
}

Result<Alignment> SdfTracker::align(const SdfField& field, const std::vector<Pose>& starts) {
  if (!frame_ready_) return makeError("no frame to align (setFrame failed or was not called)");
  if (starts.empty()) return makeError("no starting pose");
  for (const Pose& start : starts)
    if (!start.matrix().allFinite()) return makeError("starting pose is not finite");
  const FieldReading reading(field);
  const float truncation = field.truncation();
  if (!(truncation > 0.0f) || !std::isfinite(truncation)) return makeError("field truncation must be finite and > 0");
  const bool photometric = params_.color_weight > 0.0f && pyramid_.hasIntensity();

  Alignment result;
  result.pose = starts.front();
  if (pyramid_.points(0).empty()) {
    result.lost_reason = LostReason::kNoValidDepth;
    return result;
  }

  const ResidualModel model{params_.loss,
                            params_.robust_scale * truncation,
                            params_.band_fraction * truncation,
                            params_.inlier_fraction * truncation,
                            photometric ? params_.color_robust_scale : 0.0f,
                            params_.depth_noise_base_m,
                            params_.depth_noise_quadratic,
                            params_.inlier_noise_multiple};
  // One sampler per worker thread for the whole frame: the field does not change while aligning.
  Samplers samplers([&field] { return field.makeSampler(); });
  const double length = std::max(pyramid_.meanDepth(), 0.1);
  const double color_weight = params_.color_weight;

  int iterations = 0;
  // Gauss-Newton on one level from `pose`; returns the systems at the last evaluated pose.
  auto solveLevel = [&](int level, Pose& pose) {
    const std::vector<Eigen::Vector3f>& points = pyramid_.points(level);
    const std::vector<float>& intensities = pyramid_.intensities(level);
    PassSystems systems;
    for (int it = 0; it < params_.max_iterations.at(static_cast<std::size_t>(level)); ++it) {
      systems = accumulate(points, intensities, samplers, model, pose);
      if (systems.depth.residuals < 6) break;  // nothing to solve for at this level
      const Matrix6d depth_hessian = systems.depth.hessian();
      const Matrix6d color_hessian = color_weight * systems.color.hessian();
      const Vector6d gradient = systems.depth.gradient() + color_weight * systems.color.gradient();
      int constrained = 0;
      const Vector6d step = constrainedStep(depth_hessian + color_hessian, gradient,
                                            balancedConditioning(depth_hessian, color_hessian, length), length,
                                            params_.solve_rcond, params_.damping, constrained);
      if (!step.allFinite()) break;
      pose = expSE3(step) * pose;
      ++iterations;
      if (step.norm() < params_.convergence_norm) break;
    }
    return systems;
  };

  // Every start on the coarsest level; the one with the most inliers there goes on.
  const int coarsest = pyramid_.levels() - 1;
  Pose pose = starts.front();
  std::size_t best_inliers = 0;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    Pose candidate = starts[k];
    solveLevel(coarsest, candidate);
    const PassSystems at =
        accumulate(pyramid_.points(coarsest), pyramid_.intensities(coarsest), samplers, model, candidate);
    if (k == 0 || at.depth.inliers > best_inliers) {
      best_inliers = at.depth.inliers;
      pose = candidate;
      result.quality.start = static_cast<int>(k);
    }
  }
  for (int level = coarsest - 1; level >= 0; --level) solveLevel(level, pose);

  pose = orthonormalized(pose);  // ~20 float-precision updates leave it slightly off SO(3)
  result.pose = pose;
  const PassSystems final_systems = accumulate(pyramid_.points(0), pyramid_.intensities(0), samplers, model, pose);
  const int start = result.quality.start;
  result.quality = assess(final_systems.depth, final_systems.color);
  result.quality.start = start;
  result.quality.iterations = iterations;
  // Directions that neither depth nor colour constrains well for its own strength.
  result.quality.constrained_dofs =
      static_cast<int>(constrainedDirections(balancedConditioning(final_systems.depth.hessian(),
                                                                  color_weight * final_systems.color.hessian(), length),
                                             length, params_.min_hessian_rcond)
                           .cols());
  result.lost_reason = judge(result.quality, truncation, starts[static_cast<std::size_t>(start)], pose);
  return result;
}

TrackingQuality SdfTracker::assess(const NormalEquations& system, const NormalEquations& color) const {
  TrackingQuality q;
  q.points = pyramid_.points(0).size();
  q.inliers = system.inliers;
  q.inlier_ratio = q.points > 0 ? static_cast<double>(q.inliers) / static_cast<double>(q.points) : 0.0;
  q.observed = system.observed;
  q.observed_agreement = q.observed > 0 ? static_cast<double>(q.inliers) / static_cast<double>(q.observed) : 0.0;
  q.rms_residual_m = q.inliers > 0 ? std::sqrt(system.inlier_sq_sum / static_cast<double>(q.inliers)) : 0.0;
  q.color_points = color.inliers;
  q.color_rms = color.inliers > 0 ? std::sqrt(color.inlier_sq_sum / static_cast<double>(color.inliers)) : 0.0;
  if (system.residuals == 0) return q;
  // The depth term's own conditioning, with the rotations scaled to metres, so that the
  // reciprocal condition measures missing constraints rather than the units.
  const Vector6d scale = depthScaling(std::max(pyramid_.meanDepth(), 0.1));
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
  if (q.rms_residual_m > params_.max_rms_fraction * truncation) return LostReason::kHighResidual;
  // In the camera frame, so the translation is how far the camera centre moved (a world-frame
  // difference would grow with the distance from the world origin).
  const Pose correction = guess.inverse() * result;
  if (correction.translation().norm() > params_.max_correction_fraction * truncation ||
      rotationAngle(correction.linear()) > params_.max_correction_rad)
    return LostReason::kDiverged;
  // Last, so that kDegenerate says the pose passed every other test: it is sound along the
  // directions depth and colour constrain, and the start's along the others.
  if (q.constrained_dofs < 6 && !params_.accept_partially_constrained) return LostReason::kDegenerate;
  return LostReason::kNone;
}

}  // namespace semfuse::tracking
