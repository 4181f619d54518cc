#pragma once
// Coarse-to-fine depth images and their back-projected points for the tracker, with the image's
// intensity at each point when the frame has colour. Buffers are kept between frames: after the
// first frame of a given size, building allocates nothing.
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::tracking {

inline constexpr int kMaxPyramidLevels = 4;

struct PyramidParams {
  int levels = 3;            // 1..kMaxPyramidLevels; level 0 is the input resolution, each next halves it
  float min_depth_m = 0.1f;  // closer or farther readings are treated as invalid
  float max_depth_m = 6.0f;
  // Depth-aware downsampling: of a 2x2 block, only readings within this distance of the block's
  // nearest reading are averaged (relative to that depth, plus an absolute floor), so that a
  // coarse pixel on an occluding edge keeps the foreground depth instead of inventing a point
  // floating between the two surfaces.
  float merge_relative = 0.03f;
  float merge_absolute_m = 0.01f;
  // Most points used per level; a level with more valid pixels is sampled on a regular pixel
  // grid (stride chosen per frame) — the alignment cost is linear in the points, and beyond a
  // few thousand more points no longer move the pose (semfuse-bench track --fine-points ...).
  std::array<std::size_t, kMaxPyramidLevels> max_points{2000, 2000, 2000, 2000};  // 0 = all
  // Gaussian blur (pixels of the input resolution) of the intensity image before it is sampled:
  // the fused colour it is compared with is blurred over a voxel, several pixels wide.
  float intensity_blur_px = 1.5f;
};

// 2x2 depth-aware downsampling (PyramidParams::merge_*): of each block, the readings within the
// merge distance of its nearest one are averaged; a block with no reading is invalid (0).
void downsampleDepth(const cv::Mat& fine, cv::Mat& coarse, const PyramidParams& params);

// Checks that depth is a non-empty CV_32FC1 image of the size the intrinsics declare, and that the
// intrinsics are usable (finite, focal lengths > 0).
Status validateDepthImage(const cv::Mat& depth, const PinholeIntrinsics& intrinsics);

class DepthPyramid {
 public:
  // depth: CV_32FC1 metres (0 or NaN = invalid) of intrinsics.width x intrinsics.height; color:
  // CV_8UC3 RGB of the same size, or empty (then there are no intensities). Fails, with the
  // reason, on an empty depth image, wrong type or size, bad intrinsics or parameters.
  Status build(const cv::Mat& depth, const cv::Mat& color, const PinholeIntrinsics& intrinsics,
               const PyramidParams& params);
  Status build(const cv::Mat& depth, const PinholeIntrinsics& intrinsics, const PyramidParams& params) {
    return build(depth, cv::Mat(), intrinsics, params);
  }

  int levels() const { return static_cast<int>(levels_.size()); }
  const cv::Mat& depth(int level) const { return levels_[level].depth; }
  // Intensity image of the level (CV_32FC1 0..1, blurred as PyramidParams says); empty without colour.
  const cv::Mat& intensity(int level) const { return levels_[level].intensity; }
  const PyramidParams& params() const { return params_; }
  const PinholeIntrinsics& intrinsics(int level) const { return levels_[level].intrinsics; }
  // Camera-frame points (metres) of the level, after subsampling.
  const std::vector<Eigen::Vector3f>& points(int level) const { return levels_[level].points; }
  // Image intensity (0..1) at each of those points; empty when the frame has no colour.
  const std::vector<float>& intensities(int level) const { return levels_[level].intensities; }
  bool hasIntensity() const { return has_intensity_; }
  // Valid pixels of the level before subsampling.
  std::size_t validPixels(int level) const { return levels_[level].valid_pixels; }
  // Mean depth of the finest level's points: the length scale that makes rotational and
  // translational parts of the Hessian comparable.
  double meanDepth() const { return mean_depth_; }

 private:
  struct Level {
    cv::Mat depth;
    cv::Mat intensity;  // CV_32FC1 0..1, empty without colour
    PinholeIntrinsics intrinsics;
    std::vector<Eigen::Vector3f> points;
    std::vector<float> intensities;
    std::size_t valid_pixels = 0;
  };
  void backProject(Level& level, std::size_t max_points);

  std::vector<Level> levels_;
  PyramidParams params_;
  bool has_intensity_ = false;
  double mean_depth_ = 0.0;
};

}  // namespace semfuse::tracking
