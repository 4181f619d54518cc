#include "ros_config.hpp"

namespace semfuse::server {

void addRosOptions(CLI::App& app, RosIngestConfig& c) {
  auto* ros = "ROS 2 input (standard topics, sensor-data QoS)";
  app.add_flag("--ros-ingest", c.enabled,
               "also read sensor_msgs depth/colour/CameraInfo and tf2_msgs /tf as one camera")
      ->group(ros);
  app.add_option("--ros.camera-id", c.camera_id, "semfuse camera id of the ROS input")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.depth-topic", c.depth_topic, "sensor_msgs/Image depth, 16UC1 mm or 32FC1 m")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.compressed-depth-topic", c.compressed_depth_topic,
                 "sensor_msgs/CompressedImage depth, compressedDepth png or rvl; when set, read instead of "
                 "--ros.depth-topic (\"\" = none)")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.camera-info-topic", c.camera_info_topic, "sensor_msgs/CameraInfo of the depth image")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.color-topic", c.color_topic,
                 "sensor_msgs/Image colour rgb8/bgr8 registered to depth (\"\" = none)")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.compressed-color-topic", c.compressed_color_topic,
                 "sensor_msgs/CompressedImage colour, jpeg or png (\"\" = none)")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.tf-topic", c.tf_topic, "tf2_msgs/TFMessage dynamic transforms")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.tf-static-topic", c.tf_static_topic, "tf2_msgs/TFMessage static transforms")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.world-frame", c.world_frame, "tf frame of the map")->group(ros)->capture_default_str();
  app.add_option("--ros.camera-frame", c.camera_frame,
                 "tf frame of the depth camera (optical); default: the depth image's frame_id")
      ->group(ros);
  app.add_option(
         "--ros.use-tf", c.use_tf,
         "take poses from tf (a frame whose tf is late is tracked once the camera had a tf pose); false = always track")
      ->group(ros)
      ->capture_default_str();
  app.add_option("--ros.pair-tolerance", c.pair_tolerance_s, "seconds between a depth and its colour stamp")
      ->group(ros)
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--ros.wait", c.wait_s, "seconds a depth image waits for colour, CameraInfo and tf")
      ->group(ros)
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--ros.pending-depth", c.pending_depth, "depth images waiting at most")
      ->group(ros)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--ros.pending-color", c.pending_color, "colour images kept for pairing")
      ->group(ros)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--ros.publish-tf", c.publish_tf, "poses published on /tf (world -> camera): tracked, all or none")
      ->group(ros)
      ->capture_default_str()
      ->check(CLI::IsMember({"tracked", "all", "none"}));
  app.add_option("--ros.tf-child-frame", c.tf_child_frame,
                 "child frame of published transforms; default: the camera frame")
      ->group(ros);
}

}  // namespace semfuse::server
