#pragma once
// Options of the ROS 2 input (--ros-ingest): which standard topics feed one semfuse camera, how
// depth and colour are paired, where poses come from, and what the server publishes on /tf.
// In YAML they live in a `ros:` section (`ros: {depth-topic: ...}`) beside `ros-ingest: true`.
#include <string>

#include <CLI/App.hpp>

namespace semfuse::server {

struct RosIngestConfig {
  bool enabled = false;
  std::string camera_id = "ros";  // the semfuse camera these topics feed

  // ROS topic names (the DDS topic is "rt" + name). An empty name is not subscribed.
  std::string depth_topic = "/camera/depth/image_raw";  // sensor_msgs/Image 16UC1 (mm) or 32FC1 (m)
  // sensor_msgs/CompressedImage compressedDepth (png or rvl). When set, the depth comes from it and
  // depth_topic is not read: image_transport publishes every image on both.
  std::string compressed_depth_topic;
  std::string camera_info_topic = "/camera/depth/camera_info";  // intrinsics of the depth image
  std::string color_topic = "/camera/color/image_raw";          // sensor_msgs/Image rgb8/bgr8, same size as depth
  std::string compressed_color_topic;                           // sensor_msgs/CompressedImage jpeg/png
  std::string tf_topic = "/tf";
  std::string tf_static_topic = "/tf_static";

  // Frames: world_frame is the map's frame; the camera frame is the depth image's
  // header.frame_id unless camera_frame names one (an optical frame: x right, y down, z forward).
  std::string world_frame = "map";
  std::string camera_frame;
  bool use_tf = true;  // false: every frame is tracked by the server, /tf is ignored

  // Pairing and waiting (seconds).
  double pair_tolerance_s = 0.02;  // largest |depth stamp - colour stamp| of a pair
  double wait_s = 0.5;             // how long a depth image waits for its colour / CameraInfo / tf
  int pending_depth = 8;           // depth images waiting at most (the oldest is dropped)
  int pending_color = 16;          // colour images kept for pairing

  // /tf output: "tracked" = poses the server estimated (a robot's own tf already holds the
  // given ones, and a second parent for the camera frame would break its tf tree), "all", "none".
  std::string publish_tf = "tracked";
  std::string tf_child_frame;  // child frame of the published transforms; default: the camera frame
};

// Declares --ros-ingest and the --ros.* options (YAML section `ros:`) on `app`.
void addRosOptions(CLI::App& app, RosIngestConfig& config);

}  // namespace semfuse::server
