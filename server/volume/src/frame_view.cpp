#include "frame_view.hpp"

#include <string>

#include <opencv2/core.hpp>

#include "semfuse/core/camera_check.hpp"

namespace semfuse::volume::detail {
namespace {

std::string sizeOf(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }

// log2(image / labels) when image = labels * 2^k for k in 0..8, else -1: then
// floor(i * labels / image) = i >> k for every index i.
int powerOfTwoRatio(int image, int labels) {
  for (int shift = 0; shift <= 8; ++shift)
    if (int64_t{labels} << shift == image) return shift;
  return -1;
}

}  // namespace

Result<FrameView> makeFrameView(const VolumeParams& params, const cv::Mat& depth, const cv::Mat& color,
                                const cv::Mat& labels, const cv::Mat& confidence, const PinholeIntrinsics& intrinsics,
                                const Pose& camera_to_world) {
  if (Status s = checkCamera(intrinsics, camera_to_world); !s) return s.errorInfo();
  if (depth.empty()) return makeError("depth: image is empty");
  if (depth.type() != CV_32FC1)
    return makeError("depth: expected CV_32FC1 (metres), got type " + std::to_string(depth.type()));
  if (depth.cols != intrinsics.width || depth.rows != intrinsics.height)
    return makeError("depth: size " + sizeOf(depth) + " differs from the intrinsics' " +
                     std::to_string(intrinsics.width) + "x" + std::to_string(intrinsics.height));
  if (!color.empty()) {
    if (color.type() != CV_8UC3)
      return makeError("color: expected CV_8UC3 (RGB), got type " + std::to_string(color.type()));
    if (color.size() != depth.size())
      return makeError("color: size " + sizeOf(color) + " differs from the depth's " + sizeOf(depth));
  }
  if (labels.empty() && !confidence.empty()) return makeError("confidence given without labels");
  if (!labels.empty()) {
    if (labels.type() != CV_16UC1)
      return makeError("labels: expected CV_16UC1, got type " + std::to_string(labels.type()));
    if (labels.cols > depth.cols || labels.rows > depth.rows)
      return makeError("labels: size " + sizeOf(labels) + " is larger than the depth's " + sizeOf(depth));
    if (!confidence.empty()) {
      if (confidence.type() != CV_32FC1)
        return makeError("confidence: expected CV_32FC1, got type " + std::to_string(confidence.type()));
      if (confidence.size() != labels.size())
        return makeError("confidence: size " + sizeOf(confidence) + " differs from the labels' " + sizeOf(labels));
    }
  }

  FrameView view;
  view.width = depth.cols;
  view.height = depth.rows;
  view.fx = static_cast<float>(intrinsics.fx);
  view.fy = static_cast<float>(intrinsics.fy);
  view.cx = static_cast<float>(intrinsics.cx);
  view.cy = static_cast<float>(intrinsics.cy);
  // Re-orthonormalise (nearest rotation via a unit quaternion) so that the tolerated drift does not
  // shear the volume, then invert as a rigid transform.
  Pose rigid = Pose::Identity();
  rigid.linear() = Eigen::Quaterniond(camera_to_world.linear()).normalized().toRotationMatrix();
  rigid.translation() = camera_to_world.translation();
  const Pose world_to_camera = rigid.inverse(Eigen::Isometry);
  view.world_to_camera_rotation = world_to_camera.linear().cast<float>();
  view.world_to_camera_translation = world_to_camera.translation().cast<float>();
  view.camera_to_world_rotation = rigid.linear().cast<float>();
  view.camera_to_world_translation = camera_to_world.translation().cast<float>();
  view.min_depth = params.min_depth;
  view.max_depth = params.max_depth;
  view.depth = depth.ptr<float>();
  view.depth_stride = depth.step1();
  if (!color.empty()) {
    view.color = color.ptr<uint8_t>();
    view.color_stride = color.step1();
  }
  if (!labels.empty()) {
    view.labels = labels.ptr<uint16_t>();
    view.label_stride = labels.step1();
    view.label_width = labels.cols;
    view.label_height = labels.rows;
    if (!confidence.empty()) {
      view.confidence = confidence.ptr<float>();
      view.confidence_stride = confidence.step1();
    }
    view.label_col.resize(static_cast<std::size_t>(depth.cols));
    view.label_row.resize(static_cast<std::size_t>(depth.rows));
    for (int u = 0; u < depth.cols; ++u) view.label_col[u] = static_cast<int>(int64_t{u} * labels.cols / depth.cols);
    for (int v = 0; v < depth.rows; ++v) view.label_row[v] = static_cast<int>(int64_t{v} * labels.rows / depth.rows);
    view.label_col_shift = powerOfTwoRatio(depth.cols, labels.cols);
    view.label_row_shift = powerOfTwoRatio(depth.rows, labels.rows);
  }
  return view;
}

}  // namespace semfuse::volume::detail
