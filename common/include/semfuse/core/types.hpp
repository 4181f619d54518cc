#pragma once
// The decoded, validated form of what travels on the wire. Everything past the wire codecs
// (volume, tracker, server logic, clients) works with these types, never with generated C structs.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

namespace semfuse {

// Pinhole camera intrinsics, in pixels, for an image of width x height.
struct PinholeIntrinsics {
  int width = 0;
  int height = 0;
  double fx = 0.0;
  double fy = 0.0;
  double cx = 0.0;
  double cy = 0.0;

  // Same camera at another resolution (pixel centres stay consistent).
  PinholeIntrinsics scaled(double factor) const {
    return {static_cast<int>(width * factor), static_cast<int>(height * factor), fx * factor, fy * factor,
            (cx + 0.5) * factor - 0.5,        (cy + 0.5) * factor - 0.5};
  }
};

// Camera-to-world rigid transform, metres.
using Pose = Eigen::Isometry3d;

// Time stamp as on the wire (ROS 2 builtin_interfaces/Time).
struct Stamp {
  int32_t sec = 0;
  uint32_t nanosec = 0;
  double seconds() const { return sec + nanosec * 1e-9; }
};

// One RGB-D frame after decoding.
//  depth: CV_32FC1, metres; 0 or NaN marks an invalid pixel.
//  color: CV_8UC3 in RGB order (not OpenCV's BGR), same size as depth; empty when absent.
struct Frame {
  std::string camera_id;
  uint64_t seq = 0;
  Stamp stamp;
  std::string frame_id;  // ROS frame id of the camera, may be empty
  PinholeIntrinsics intrinsics;
  cv::Mat depth;
  cv::Mat color;
  std::optional<Pose> camera_to_world;
};

// Per-pixel labels for one frame, after decoding.
//  labels: CV_16UC1, 0 = unlabeled. confidence: CV_32FC1 in [0, 1], same size as labels.
//  instances: CV_16UC1 of the labels' size from a panoptic segmenter, the object instance of each
//  pixel (0 = none; the ids are the segmenter's own and need not agree from frame to frame);
//  empty from a segmenter that gives classes only.
//  The size may be smaller than the frame's; consumers upsample nearest-neighbour.
struct Segmentation {
  std::string camera_id;
  uint64_t frame_seq = 0;
  std::string segmenter_id;
  Stamp stamp;
  cv::Mat labels;
  cv::Mat confidence;
  cv::Mat instances;
};

// What the server did with a frame's pose (values as TrackedPose_Constants on the wire).
enum class PoseState : uint8_t {
  kGiven = 0,    // integrated at the pose the frame carried
  kTracked = 1,  // estimated by SDF alignment
  kRefined = 2,  // given pose refined by SDF alignment
  kLost = 3,     // alignment failed: frame not integrated
};

// The pose the server used for one frame, and how it got it.
struct TrackedPose {
  std::string camera_id;
  uint64_t seq = 0;
  Stamp stamp;
  std::string frame_id;
  PoseState state = PoseState::kGiven;
  bool posed = false;  // has a pose and goes to the map; false when tracking is lost
  Pose camera_to_world = Pose::Identity();
  float inlier_ratio = 0.0f;
  float residual = 0.0f;
  uint32_t iterations = 0;
  float track_ms = 0.0f;
};

}  // namespace semfuse
