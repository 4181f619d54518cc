#pragma once
// Test helper: the first crossing of the trilinear TSDF along one pixel's ray, by brute force
// (the truth that raycasts are judged against where they disagree).
#include <Eigen/Core>

#include "semfuse/core/types.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::render::testing {

// Camera depth of the first crossing of the trilinear TSDF along pixel (u, v)'s ray, found by
// brute force: samples every 1/50 voxel from min_depth to max_depth, the first positive sample
// followed by a non-positive one, both valid (0 when none). Where the ray enters observed cells
// from unobserved ones, the value just past the boundary (found by bisection) counts as a sample:
// a crossing right behind the boundary of what the cameras saw is a crossing too (the fast path
// finds those; the plain march, whose last sample before them was invalid, does not). Slow; for a
// few pixels only. The value just before the ray leaves observed cells counts the same way.
inline double denseFirstCrossing(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& pose,
                                 int u, int v, const RaycastOptions& options) {
  volume::VolumeSampler sampler(volume);
  const Eigen::Vector3d direction = pose.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  auto valueAt = [&](double t, float& f) {
    return sampler.tsdf(Eigen::Vector3d(pose.translation() + t * direction), f);
  };
  const double step = volume.voxelSize() / 50.0 / direction.norm();
  // The last valid ray parameter between a valid and an invalid one (either order).
  auto boundary = [&](double valid, double invalid) {
    for (int i = 0; i < 30; ++i) {
      const double mid = 0.5 * (invalid + valid);
      float f_mid;
      (valueAt(mid, f_mid) ? valid : invalid) = mid;
    }
    return valid;
  };
  bool have_positive = false, previous_valid = false;
  double t_prev = 0.0;
  float f_prev = 0.0f;
  for (double t = options.min_depth; t < options.max_depth; t += step) {
    float f;
    if (!valueAt(t, f)) {
      if (previous_valid && have_positive) {  // the value just before the boundary, likewise
        const double valid = boundary(t - step, t);
        float f_exit;
        if (valueAt(valid, f_exit) && f_exit <= 0.0f) return t_prev + (valid - t_prev) * f_prev / (f_prev - f_exit);
      }
      have_positive = previous_valid = false;
      continue;
    }
    if (!previous_valid && t > options.min_depth) {
      const double valid = boundary(t, t - step);
      float f_entry;
      if (valueAt(valid, f_entry) && f_entry > 0.0f) {
        have_positive = true;
        t_prev = valid;
        f_prev = f_entry;
      }
    }
    previous_valid = true;
    if (have_positive && f <= 0.0f) return t_prev + (t - t_prev) * f_prev / (f_prev - f);
    have_positive = f > 0.0f;
    t_prev = t;
    f_prev = f;
  }
  return 0.0;
}

}  // namespace semfuse::render::testing
