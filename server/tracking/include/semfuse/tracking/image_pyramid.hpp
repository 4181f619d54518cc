#pragma once
// Small intensity and depth images of a frame (1/4, 1/8 and 1/16 of a 640x480 input) for dense
// image alignment (rgbd_odometry.hpp): frame to frame, which gives the SDF alignment a start that
// survives fast motion, and frame to keyframe, which turns a keyframe's pose into the pose of a
// frame that sees the same place. Keyframes keep theirs (a few tens of KiB).
#include <array>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::tracking {

class DepthPyramid;

struct ImageLevel {
  cv::Mat intensity;  // CV_32FC1, 0..1; empty when the frame has no colour
  cv::Mat depth;      // CV_32FC1 metres, 0 = invalid
  PinholeIntrinsics intrinsics;
};

class ImagePyramid {
 public:
  static constexpr int kLevels = 4;  // index 0 is the finest

  // From a built depth pyramid: its coarsest level (1/4 of the input when it has 3 levels) is
  // this one's finest; the next two halve it with the same depth-aware merging.
  void build(const DepthPyramid& frame);

  // Frees the levels finer than `level`.
  void releaseFinerThan(int level);

  // A deep copy of the levels from `level` on (keyframes keep only the coarse ones). Copying an
  // ImagePyramid by value shares its pixels, and build() reuses its buffers: a kept pyramid that
  // shared them would turn into a later frame's images.
  ImagePyramid cloneFrom(int level) const;

  bool empty() const { return levels_[kLevels - 1].depth.empty(); }
  bool hasIntensity() const { return !levels_[kLevels - 1].intensity.empty(); }
  // The finest level that holds images (0 unless released).
  int finestLevel() const;
  const ImageLevel& level(int index) const { return levels_[static_cast<std::size_t>(index)]; }

 private:
  std::array<ImageLevel, kLevels> levels_;
};

}  // namespace semfuse::tracking
