#pragma once
// The small scene the server core's tests fuse: a 64x48 camera in front of a flat wall, on a
// 2 cm map with the synthetic legend. Cheap enough that a test can push dozens of frames.
#include <string>

#include <opencv2/core.hpp>

#include "mapper.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::server::wall_scene {

inline constexpr int kWallWidth = 64, kWallHeight = 48;

inline MapperOptions wallMapOptions(double voxel_size = 0.02) {
  MapperOptions options;
  options.volume.voxel_size = voxel_size;
  options.volume.truncation = 0.08;
  options.legend = *builtinLegend("synthetic");
  return options;
}

// A wall 1.5 m in front of the camera; with a pose, the camera at the origin.
inline Frame wallFrame(const std::string& camera, uint64_t seq, bool with_pose) {
  Frame frame;
  frame.camera_id = camera;
  frame.seq = seq;
  frame.intrinsics = {kWallWidth, kWallHeight, 50.0, 50.0, kWallWidth / 2.0 - 0.5, kWallHeight / 2.0 - 0.5};
  frame.depth = cv::Mat(kWallHeight, kWallWidth, CV_32FC1, cv::Scalar(1.5f));
  if (with_pose) frame.camera_to_world = Pose::Identity();
  return frame;
}

}  // namespace semfuse::server::wall_scene
