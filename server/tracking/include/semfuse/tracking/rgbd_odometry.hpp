#pragma once
// Dense alignment of two RGB-D images (Kerl, Sturm and Cremers, ICRA 2013; Steinbruecker et al.
// 2011): the motion that carries the reference image's points onto the current image so that
// intensities match (photometric term) and depths match (geometric term), coarse to fine over
// small images. Its basin is measured in pixels of the coarsest image, several degrees and
// centimetres, where the SDF alignment's is the truncation band; it gives that alignment its
// start after fast motion and turns a keyframe's pose into a relocalisation candidate.
#include <array>
#include <cstddef>

#include "semfuse/core/types.hpp"
#include "semfuse/tracking/image_pyramid.hpp"

namespace semfuse::tracking {

struct OdometryParams {
  std::array<int, ImagePyramid::kLevels> max_iterations{6, 8, 12, 16};  // index 0 = finest
  // Reference points per level at most, on a regular grid (0 = every pixel with depth). The
  // alignment only starts the SDF alignment, which refines it against the map, so a quarter of
  // the finest level's pixels is enough (semfuse-bench track --odometry-points).
  std::array<std::size_t, ImagePyramid::kLevels> max_points{4800, 0, 0, 0};
  float intensity_scale = 0.04f;         // Huber scale of intensity residuals (0..1)
  float depth_scale_m = 0.02f;           // Huber scale of depth residuals
  float max_depth_difference_m = 0.15f;  // a larger disagreement is an occlusion: the point is left out
  // Depth residuals count this much against intensity ones (intensity^2 per metre^2).
  float depth_weight = 4.0f;
  double convergence_norm = 1e-4;
};

struct OdometryResult {
  Pose current_from_reference = Pose::Identity();  // maps reference-camera points into the current camera
  std::size_t points = 0;                          // reference points evaluated on the finest level at the end
  std::size_t landed = 0;                          // of those, landed in the current image where it has depth
  std::size_t matched = 0;                         // of those, with a depth that agrees
  double overlap = 0.0;                            // landed / points: how much of the reference the current image sees
  double matched_ratio = 0.0;                      // matched / landed: how well the two agree where they overlap
  double intensity_rms = 0.0;                      // over the points with an intensity residual
};

// Aligns `reference` to `current` from `initial` (current_from_reference), coarse to fine down to
// the finest level both pyramids hold. Needs depth in both and uses intensity where both have it.
// Stateless and cheap (a few ms on 160x120).
OdometryResult alignImages(const ImagePyramid& reference, const ImagePyramid& current, const Pose& initial,
                           const OdometryParams& params = {});

}  // namespace semfuse::tracking
