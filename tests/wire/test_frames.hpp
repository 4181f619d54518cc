#pragma once
// Deterministic test frames with structure (gradients, invalid pixels) so codecs are exercised.
#include <cmath>

#include <opencv2/core.hpp>

#include "semfuse/core/types.hpp"

namespace semfuse::wire::testing {

inline Frame makeFrame(int width = 64, int height = 48, bool with_color = true) {
  Frame frame;
  frame.camera_id = "cam0";
  frame.seq = 17;
  frame.stamp = {12, 345000000};
  frame.frame_id = "camera_optical";
  frame.intrinsics = {width, height, 50.0, 51.0, width / 2.0 - 0.5, height / 2.0 - 0.5};
  frame.depth.create(height, width, CV_32FC1);
  if (with_color) frame.color.create(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // Whole millimetres, so the 16-bit encodings are exact.
      frame.depth.at<float>(y, x) = ((x + y) % 11 == 0) ? 0.0f : static_cast<float>(500 + 7 * x + 13 * y) * 0.001f;
      if (with_color)
        frame.color.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uint8_t>(4 * x), static_cast<uint8_t>(5 * y), 200);
    }
  }
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.5, -1.25, 2.0);
  frame.camera_to_world = pose;
  return frame;
}

}  // namespace semfuse::wire::testing
