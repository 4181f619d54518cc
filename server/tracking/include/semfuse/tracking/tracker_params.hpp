#pragma once
// Parameters of the SDF tracker. Distances that depend on the map are given as fractions of the
// TSDF truncation, so that one set of defaults works for any voxel size.
#include <array>

#include "semfuse/tracking/depth_pyramid.hpp"

namespace semfuse::tracking {

enum class RobustLoss {
  kHuber,   // quadratic up to the scale, linear beyond (convex: safe from a poor start)
  kCauchy,  // log(1 + (r/c)^2): down-weights gross outliers harder (moving objects, new geometry)
};

struct TrackerParams {
  PyramidParams pyramid;
  // Gauss-Newton iterations per pyramid level, index 0 = finest. The coarse level takes the
  // large steps cheaply; the finest only polishes. From a large offset (~10 degrees) most points
  // start outside the truncation band and the few inside pull the pose in over 20-40 small steps;
  // between consecutive frames the convergence test ends the coarse level after a few.
  std::array<int, kMaxPyramidLevels> max_iterations{2, 8, 40, 40};
  // Converged when the update twist is this small (metres and radians together).
  double convergence_norm = 1e-4;

  RobustLoss loss = RobustLoss::kHuber;
  float robust_scale = 0.25f;  // x truncation
  // A point is used only where |D| < band_fraction x truncation: at the truncation limit the
  // field is flat (no gradient) and tells nothing about where the surface is.
  float band_fraction = 0.95f;
  float inlier_fraction = 0.5f;  // |D| below this x truncation counts as an inlier
  // ... or below inlier_noise_multiple x the depth noise at the point's range, which grows with
  // the square of the range: sigma(z) = base + quadratic (z - 0.4 m)^2 (structured-light sensors,
  // Nguyen, Izadi and Lovell 2012: ~2 mm at 1 m, ~14 mm at 3 m).
  float depth_noise_base_m = 0.0012f;
  float depth_noise_quadratic = 0.0019f;
  float inlier_noise_multiple = 2.5f;
  // Levenberg damping added to the Hessian diagonal, relative to its mean; keeps a nearly
  // degenerate step bounded (the quality checks below still flag the frame).
  double damping = 1e-4;
  // Directions of the (depth-scaled) Hessian with less than this fraction of its largest
  // eigenvalue are left where the starting guess put them instead of being solved for: a plane
  // or a corridor constrains only some degrees of freedom, and a step along the others would be
  // noise.
  double solve_rcond = 1e-3;
  // Whether a frame whose depth and colour together leave some directions unconstrained (below
  // min_hessian_rcond) is still trusted, with the start's values along those directions.
  bool accept_partially_constrained = false;

  // Photometric term: the frame's intensity against the fused colour of the map at the same
  // point, added to the depth term with this weight (metres^2 per intensity^2: a residual of
  // 0.1 in intensity costs as much as sqrt(weight) * 0.1 m of depth). 0 = depth only. Colour
  // holds the pose where the depth alone slides (planes, fast motion); 0.1 is the best of
  // 0.03-1 on freiburg1_xyz (semfuse-bench track --color-weight).
  float color_weight = 0.1f;
  float color_robust_scale = 0.1f;  // Huber scale of the intensity residual (intensity 0..1)

  // A frame is LOST, and must not be integrated, below any of these.
  double min_inlier_ratio = 0.3;  // inliers / valid points of the finest level
  // RMS of D over the inliers, x truncation. Inliers reach 0.5 x truncation (more at long range),
  // so a correct pose of a noisy frame has an RMS near 0.35: freiburg1_xyz's fast stretches reach
  // 0.36 at poses the motion capture confirms, and the agreement tests catch wrong poses first.
  double max_rms_fraction = 0.45;
  std::size_t min_inliers = 200;
  // Reciprocal condition (min / max eigenvalue) of the 6x6 Hessian with rotations scaled by the
  // mean scene depth (so both blocks are in metres): a plane or a corridor leaves directions
  // unconstrained, its min eigenvalue collapses and the pose along them would be noise.
  double min_hessian_rcond = 2e-3;
  // Larger corrections than these from the starting guess are treated as divergence. The basin
  // of convergence is about the truncation band: from farther away most points start in the flat
  // truncated region or in unobserved space, and the few that pull settle on whatever surface is
  // near (a 50 cm jump in a room slid along the walls to a pose 40 cm off with 43 % inliers, which
  // no residual test could tell from new territory). A correction beyond the band is therefore
  // not trusted, whatever the residuals say.
  float max_correction_fraction = 2.0f;  // x truncation, camera centre
  double max_correction_rad = 0.25;      // ~14 degrees: 10 degree offsets are still recovered
};

}  // namespace semfuse::tracking
