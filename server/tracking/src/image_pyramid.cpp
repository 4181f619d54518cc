#include "semfuse/tracking/image_pyramid.hpp"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "semfuse/tracking/depth_pyramid.hpp"

namespace semfuse::tracking {

void ImagePyramid::build(const DepthPyramid& frame) {
  const int source = std::min(frame.levels(), 3) - 1;
  ImageLevel& finest = levels_[0];
  frame.depth(source).copyTo(finest.depth);
  finest.intrinsics = frame.intrinsics(source);
  if (frame.intensity(source).empty()) {
    finest.intensity.release();
  } else {
    frame.intensity(source).copyTo(finest.intensity);
  }
  for (int l = 1; l < kLevels; ++l) {
    ImageLevel& fine = levels_[static_cast<std::size_t>(l - 1)];
    ImageLevel& coarse = levels_[static_cast<std::size_t>(l)];
    downsampleDepth(fine.depth, coarse.depth, frame.params());
    if (fine.intensity.empty()) {
      coarse.intensity.release();
    } else {
      cv::resize(fine.intensity, coarse.intensity, coarse.depth.size(), 0, 0, cv::INTER_AREA);
    }
    coarse.intrinsics = fine.intrinsics.scaled(0.5);
    coarse.intrinsics.width = coarse.depth.cols;
    coarse.intrinsics.height = coarse.depth.rows;
  }
}

void ImagePyramid::releaseFinerThan(int level) {
  for (int l = 0; l < level && l < kLevels; ++l) {
    levels_[static_cast<std::size_t>(l)].depth.release();
    levels_[static_cast<std::size_t>(l)].intensity.release();
  }
}

ImagePyramid ImagePyramid::cloneFrom(int level) const {
  ImagePyramid out;
  for (int l = std::max(level, 0); l < kLevels; ++l) {
    const ImageLevel& from = levels_[static_cast<std::size_t>(l)];
    ImageLevel& to = out.levels_[static_cast<std::size_t>(l)];
    to.depth = from.depth.clone();
    to.intensity = from.intensity.clone();
    to.intrinsics = from.intrinsics;
  }
  return out;
}

int ImagePyramid::finestLevel() const {
  int l = 0;
  while (l < kLevels - 1 && levels_[static_cast<std::size_t>(l)].depth.empty()) ++l;
  return l;
}

}  // namespace semfuse::tracking
