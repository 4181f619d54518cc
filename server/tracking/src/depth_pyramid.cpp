#include "semfuse/tracking/depth_pyramid.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/core/camera_check.hpp"

namespace semfuse::tracking {

Status validateDepthImage(const cv::Mat& depth, const PinholeIntrinsics& k) {
  if (depth.empty()) return makeError("depth image is empty");
  if (depth.type() != CV_32FC1)
    return makeError("depth image must be CV_32FC1 metres, got OpenCV type " + std::to_string(depth.type()));
  if (depth.cols != k.width || depth.rows != k.height)
    return makeError("depth image is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
                     " but the intrinsics say " + std::to_string(k.width) + "x" + std::to_string(k.height));
  return checkProjection(k);
}

namespace {

Status validate(const cv::Mat& depth, const PinholeIntrinsics& k, const PyramidParams& p) {
  if (Status status = validateDepthImage(depth, k); !status) return status;
  if (p.levels < 1 || p.levels > kMaxPyramidLevels)
    return makeError("pyramid levels must be within 1.." + std::to_string(kMaxPyramidLevels) + ", got " +
                     std::to_string(p.levels));
  if ((k.width >> (p.levels - 1)) < 8 || (k.height >> (p.levels - 1)) < 8)
    return makeError("image of " + std::to_string(k.width) + "x" + std::to_string(k.height) + " is too small for " +
                     std::to_string(p.levels) + " pyramid levels");
  if (!(p.min_depth_m >= 0.0f) || !(p.max_depth_m > p.min_depth_m))
    return makeError("depth range must satisfy 0 <= min_depth_m < max_depth_m");
  return Status::Ok();
}

// Copies the input, replacing NaN, infinite and out-of-range readings by 0 (invalid), so that
// every later stage tests validity with a single comparison.
void sanitize(const cv::Mat& in, cv::Mat& out, float min_depth, float max_depth) {
  out.create(in.rows, in.cols, CV_32FC1);
  tbb::parallel_for(tbb::blocked_range<int>(0, in.rows, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* src = in.ptr<float>(v);
      float* dst = out.ptr<float>(v);
      for (int u = 0; u < in.cols; ++u) {
        const float z = src[u];
        dst[u] = (z >= min_depth && z <= max_depth) ? z : 0.0f;  // false for NaN
      }
    }
  });
}

}  // namespace

void downsampleDepth(const cv::Mat& fine, cv::Mat& coarse, const PyramidParams& params) {
  const float merge_relative = params.merge_relative;
  const float merge_absolute = params.merge_absolute_m;
  coarse.create(fine.rows / 2, fine.cols / 2, CV_32FC1);
  tbb::parallel_for(tbb::blocked_range<int>(0, coarse.rows, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      const float* top = fine.ptr<float>(2 * v);
      const float* bottom = fine.ptr<float>(2 * v + 1);
      float* dst = coarse.ptr<float>(v);
      for (int u = 0; u < coarse.cols; ++u) {
        const float block[4] = {top[2 * u], top[2 * u + 1], bottom[2 * u], bottom[2 * u + 1]};
        float nearest = 0.0f;
        for (float z : block)
          if (z > 0.0f && (nearest == 0.0f || z < nearest)) nearest = z;
        if (nearest == 0.0f) {
          dst[u] = 0.0f;
          continue;
        }
        const float limit = nearest + merge_absolute + merge_relative * nearest;
        float sum = 0.0f;
        int count = 0;
        for (float z : block)
          if (z > 0.0f && z <= limit) {
            sum += z;
            ++count;
          }
        dst[u] = sum / static_cast<float>(count);
      }
    }
  });
}

Status DepthPyramid::build(const cv::Mat& depth, const cv::Mat& color, const PinholeIntrinsics& intrinsics,
                           const PyramidParams& params) {
  if (Status status = validate(depth, intrinsics, params); !status) return status;
  if (!color.empty() && (color.type() != CV_8UC3 || color.size() != depth.size()))
    return makeError("colour image must be CV_8UC3 RGB of the depth image's size");
  levels_.resize(static_cast<std::size_t>(params.levels));
  params_ = params;
  levels_[0].intrinsics = intrinsics;
  sanitize(depth, levels_[0].depth, params.min_depth_m, params.max_depth_m);
  has_intensity_ = !color.empty();
  if (has_intensity_) {
    cv::Mat grey;
    cv::cvtColor(color, grey, cv::COLOR_RGB2GRAY);
    grey.convertTo(levels_[0].intensity, CV_32F, 1.0 / 255.0);
    if (params.intensity_blur_px > 0.0f)
      cv::GaussianBlur(levels_[0].intensity, levels_[0].intensity, cv::Size(), params.intensity_blur_px);
  } else {
    for (Level& level : levels_) level.intensity.release();
  }
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    downsampleDepth(levels_[l - 1].depth, levels_[l].depth, params);
    if (has_intensity_)
      cv::resize(levels_[l - 1].intensity, levels_[l].intensity, levels_[l].depth.size(), 0, 0, cv::INTER_AREA);
    levels_[l].intrinsics = levels_[l - 1].intrinsics.scaled(0.5);
    levels_[l].intrinsics.width = levels_[l].depth.cols;
    levels_[l].intrinsics.height = levels_[l].depth.rows;
  }
  for (std::size_t l = 0; l < levels_.size(); ++l) backProject(levels_[l], params.max_points.at(l));

  double depth_sum = 0.0;
  for (const Eigen::Vector3f& p : levels_[0].points) depth_sum += p.z();
  mean_depth_ = levels_[0].points.empty() ? 0.0 : depth_sum / static_cast<double>(levels_[0].points.size());
  return Status::Ok();
}

void DepthPyramid::backProject(Level& level, std::size_t max_points) {
  const cv::Mat& depth = level.depth;
  level.valid_pixels = static_cast<std::size_t>(cv::countNonZero(depth));
  // Regular grid stride so that about max_points valid pixels remain; regular rather than random
  // so that a frame gives the same points every run.
  int stride = 1;
  if (max_points > 0)
    while (level.valid_pixels / static_cast<std::size_t>(stride * stride) > max_points) ++stride;

  level.points.clear();  // keeps the capacity: no allocation after the first frame
  level.intensities.clear();
  level.points.reserve(static_cast<std::size_t>(depth.rows) * static_cast<std::size_t>(depth.cols));
  const bool with_intensity = !level.intensity.empty();
  const PinholeIntrinsics& k = level.intrinsics;
  const float inv_fx = static_cast<float>(1.0 / k.fx);
  const float inv_fy = static_cast<float>(1.0 / k.fy);
  const float cx = static_cast<float>(k.cx);
  const float cy = static_cast<float>(k.cy);
  // Offset the grid by half a stride so that subsampled levels do not all hug the top-left edge.
  for (int v = stride / 2; v < depth.rows; v += stride) {
    const float* row = depth.ptr<float>(v);
    const float* intensity = with_intensity ? level.intensity.ptr<float>(v) : nullptr;
    for (int u = stride / 2; u < depth.cols; u += stride) {
      const float z = row[u];
      if (z <= 0.0f) continue;
      level.points.emplace_back((static_cast<float>(u) - cx) * z * inv_fx, (static_cast<float>(v) - cy) * z * inv_fy,
                                z);
      if (with_intensity) level.intensities.push_back(intensity[u]);
    }
  }
}

}  // namespace semfuse::tracking
