#pragma once
// ROS 2 input and /tf output of the server (--ros-ingest). One thread waits on best-effort
// readers of standard topics (sensor_msgs Image / CompressedImage (colour, or compressedDepth
// PNG / RVL depth) / CameraInfo, tf2_msgs
// TFMessage on /tf and /tf_static), decodes each sample, lets RosFrameAssembler pair them into
// Frames and hands those to the same per-camera queue as the native ingest. Every image given
// up is counted in ServerStatus with its reason. Poses the server uses go out on /tf.
#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include <opencv2/core/mat.hpp>

#include "frame_queue.hpp"
#include "mapper.hpp"
#include "ros_config.hpp"
#include "ros_frame_assembler.hpp"
#include "ros_tf_buffer.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "sensor_msgs.h"
#include "server_state.hpp"
#include "tf2_msgs.h"

namespace semfuse::server {

class RosIngest {
 public:
  // Throws std::runtime_error on an unusable configuration (no depth topic, no world frame).
  RosIngest(const dds::Participant& participant, const RosIngestConfig& config, FrameQueue& frames, ServerState& state);
  ~RosIngest();

  void start();
  void stop();

  // Publishes world -> camera for a posed frame on /tf, as --ros.publish-tf asks (tracking threads).
  void publishPose(const Frame& frame, const TrackOutcome& outcome);

 private:
  template <class T>
  struct Input {
    Input(const dds::Participant& participant, const std::string& ros_topic, const dds::Qos& qos);
    dds::Topic<T> topic;
    dds::Reader<T> reader;
    dds::ReadCondition ready;
  };

  void run();
  void takeAll();
  void onDepth(const sensor_msgs_msg_dds__Image_& msg);
  void onCompressedDepth(const sensor_msgs_msg_dds__CompressedImage_& msg);
  // A depth image of either depth topic: numbered and counted, decoded (timed as the frame decode
  // stage), then handed to the assembler or rejected with why it did not decode.
  void addDepth(const std_msgs_msg_dds__Header_& header, const std::function<Result<cv::Mat>()>& decode,
                const char* what);
  void onColor(const sensor_msgs_msg_dds__Image_& msg);
  void onCompressedColor(const sensor_msgs_msg_dds__CompressedImage_& msg);
  void onCameraInfo(const sensor_msgs_msg_dds__CameraInfo_& msg);
  void onTf(const tf2_msgs_msg_dds__TFMessage_& msg, bool is_static);
  void flush();
  void count(const RosFrameAssembler::Drop& drop);

  const RosIngestConfig config_;
  FrameQueue& frames_;
  ServerState& state_;
  TfBuffer tf_;
  RosFrameAssembler assembler_;
  uint64_t next_seq_ = 1;
  bool warned_tf_gap_ = false;

  std::unique_ptr<Input<sensor_msgs_msg_dds__Image_>> depth_;
  std::unique_ptr<Input<sensor_msgs_msg_dds__CompressedImage_>> compressed_depth_;
  std::unique_ptr<Input<sensor_msgs_msg_dds__Image_>> color_;
  std::unique_ptr<Input<sensor_msgs_msg_dds__CompressedImage_>> compressed_color_;
  std::unique_ptr<Input<sensor_msgs_msg_dds__CameraInfo_>> camera_info_;
  std::unique_ptr<Input<tf2_msgs_msg_dds__TFMessage_>> tf_in_;
  std::unique_ptr<Input<tf2_msgs_msg_dds__TFMessage_>> tf_static_in_;
  dds::Topic<tf2_msgs_msg_dds__TFMessage_> tf_out_topic_;
  dds::Writer<tf2_msgs_msg_dds__TFMessage_> tf_writer_;
  std::mutex tf_writer_mutex_;
  dds::GuardCondition stop_;
  dds::WaitSet waitset_;
  std::thread thread_;
};

}  // namespace semfuse::server
