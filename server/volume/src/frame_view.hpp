#pragma once
// Internal: the validated, raw-pointer view of one frame that the integration kernels read.
// Built once per call so that the per-voxel loops see only floats and pointers.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/volume_params.hpp"

namespace semfuse::volume::detail {

struct FrameView {
  int width = 0, height = 0;
  float fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix3f world_to_camera_rotation;
  Eigen::Vector3f world_to_camera_translation;
  Eigen::Matrix3f camera_to_world_rotation;
  Eigen::Vector3f camera_to_world_translation;
  float min_depth = 0, max_depth = 0;

  const float* depth = nullptr;  // row r starts at depth + r * depth_stride
  std::size_t depth_stride = 0;
  const uint8_t* color = nullptr;  // RGB, nullptr when absent
  std::size_t color_stride = 0;
  const uint16_t* labels = nullptr;  // nullptr when absent
  std::size_t label_stride = 0;
  int label_width = 0, label_height = 0;
  const float* confidence = nullptr;  // nullptr: confidence 1 everywhere
  std::size_t confidence_stride = 0;
  // Nearest-neighbour upsampling of the label image: depth column/row -> label column/row.
  std::vector<int> label_col, label_row;
  // When the depth is 2^shift times the labels' size along an axis (equal size: 0), the mapping
  // above is a shift, which vector code computes instead of looking it up; -1 otherwise.
  int label_col_shift = -1, label_row_shift = -1;

  bool validDepth(float d) const { return d >= min_depth && d <= max_depth; }  // false for NaN
};

// Checks every input and builds the view; the error names the offending input.
Result<FrameView> makeFrameView(const VolumeParams& params, const cv::Mat& depth, const cv::Mat& color,
                                const cv::Mat& labels, const cv::Mat& confidence, const PinholeIntrinsics& intrinsics,
                                const Pose& camera_to_world);

}  // namespace semfuse::volume::detail
