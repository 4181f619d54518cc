#include "ros_ingest.hpp"

#include <chrono>
#include <stdexcept>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/wire/ros_codec.hpp"

namespace semfuse::server {
namespace {

// ROS name "/camera/depth/image_raw" -> DDS topic "rt/camera/depth/image_raw".
std::string ddsTopic(const std::string& ros_name) {
  return "rt" + (ros_name.rfind('/', 0) == 0 ? ros_name : "/" + ros_name);
}

// tf readers: depth like rclcpp's tf listener; best-effort matches any /tf publisher. Our own
// /tf output is ignored, or the poses the server publishes would come back as input.
dds::Qos tfQos() {
  dds::Qos qos = dds::qos::sensorData();
  qos.keepLast(100);
  dds_qset_ignorelocal(qos.get(), DDS_IGNORELOCAL_PARTICIPANT);
  return qos;
}
// /tf_static publishers are reliable + transient-local: the reader must be too, to get the
// transforms published before it started.
dds::Qos tfStaticQos() {
  dds::Qos qos;
  qos.reliable(dds::qos::kMaxBlockingTime).keepLast(100).transientLocal();
  dds_qset_ignorelocal(qos.get(), DDS_IGNORELOCAL_PARTICIPANT);
  return qos;
}
// What rclcpp's TransformBroadcaster uses.
dds::Qos tfWriterQos() {
  dds::Qos qos;
  qos.reliable(dds::qos::kMaxBlockingTime).keepLast(100).volatileDurability();
  return qos;
}

std::string text(const char* s) { return s ? s : ""; }

RosFrameAssembler::Options assemblerOptions(const RosIngestConfig& c) {
  RosFrameAssembler::Options o;
  o.camera_id = c.camera_id;
  o.expect_color = !c.color_topic.empty() || !c.compressed_color_topic.empty();
  o.pair_tolerance_s = c.pair_tolerance_s;
  o.wait_s = c.wait_s;
  o.pending_depth = static_cast<size_t>(c.pending_depth);
  o.pending_color = static_cast<size_t>(c.pending_color);
  o.use_tf = c.use_tf;
  o.camera_frame = c.camera_frame;
  return o;
}

const RosIngestConfig& checked(const RosIngestConfig& c) {
  if (c.depth_topic.empty() && c.compressed_depth_topic.empty()) {
    throw std::runtime_error("--ros.depth-topic or --ros.compressed-depth-topic: a depth topic is needed");
  }
  if (c.camera_id.empty()) throw std::runtime_error("--ros.camera-id must not be empty");
  if (c.use_tf && c.world_frame.empty()) throw std::runtime_error("--ros.world-frame: needed with --ros.use-tf");
  if (c.pending_depth < 1 || c.pending_color < 1) throw std::runtime_error("--ros.pending-*: at least 1");
  return c;
}
}  // namespace

template <class T>
RosIngest::Input<T>::Input(const dds::Participant& participant, const std::string& ros_topic, const dds::Qos& qos)
    : topic(participant, ddsTopic(ros_topic)), reader(topic, qos), ready(reader.handle()) {}

RosIngest::RosIngest(const dds::Participant& participant, const RosIngestConfig& config, FrameQueue& frames,
                     ServerState& state)
    : config_(checked(config)),
      frames_(frames),
      state_(state),
      assembler_(assemblerOptions(config_)),
      tf_out_topic_(participant, "rt/tf"),
      tf_writer_(tf_out_topic_, tfWriterQos()),
      stop_(participant),
      waitset_(participant) {
  const dds::Qos sensor = dds::qos::sensorData();
  if (config_.compressed_depth_topic.empty()) {
    depth_ = std::make_unique<Input<sensor_msgs_msg_dds__Image_>>(participant, config_.depth_topic, sensor);
    waitset_.attach(depth_->ready.handle());
  } else {
    compressed_depth_ = std::make_unique<Input<sensor_msgs_msg_dds__CompressedImage_>>(
        participant, config_.compressed_depth_topic, sensor);
    waitset_.attach(compressed_depth_->ready.handle());
  }
  camera_info_ =
      std::make_unique<Input<sensor_msgs_msg_dds__CameraInfo_>>(participant, config_.camera_info_topic, sensor);
  waitset_.attach(camera_info_->ready.handle());
  if (!config_.color_topic.empty()) {
    color_ = std::make_unique<Input<sensor_msgs_msg_dds__Image_>>(participant, config_.color_topic, sensor);
    waitset_.attach(color_->ready.handle());
  }
  if (!config_.compressed_color_topic.empty()) {
    compressed_color_ = std::make_unique<Input<sensor_msgs_msg_dds__CompressedImage_>>(
        participant, config_.compressed_color_topic, sensor);
    waitset_.attach(compressed_color_->ready.handle());
  }
  if (config_.use_tf && !config_.tf_topic.empty()) {
    tf_in_ = std::make_unique<Input<tf2_msgs_msg_dds__TFMessage_>>(participant, config_.tf_topic, tfQos());
    waitset_.attach(tf_in_->ready.handle());
  }
  if (config_.use_tf && !config_.tf_static_topic.empty()) {
    tf_static_in_ =
        std::make_unique<Input<tf2_msgs_msg_dds__TFMessage_>>(participant, config_.tf_static_topic, tfStaticQos());
    waitset_.attach(tf_static_in_->ready.handle());
  }
  waitset_.attach(stop_.handle());
  spdlog::info("ROS 2 input: camera '{}' from {} ({}{}), CameraInfo {}, poses {}", config_.camera_id,
               config_.compressed_depth_topic.empty() ? config_.depth_topic
                                                      : config_.compressed_depth_topic + " (compressed depth)",
               config_.color_topic.empty() ? "no colour" : "colour " + config_.color_topic,
               config_.compressed_color_topic.empty() ? "" : ", compressed " + config_.compressed_color_topic,
               config_.camera_info_topic,
               config_.use_tf ? "from tf " + config_.world_frame + " -> " +
                                    (config_.camera_frame.empty() ? "<image frame_id>" : config_.camera_frame)
                              : "tracked");
}

RosIngest::~RosIngest() { stop(); }

void RosIngest::start() {
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-ros-ingest");
    run();
  });
}

void RosIngest::stop() {
  if (!thread_.joinable()) return;
  stop_.trigger();
  thread_.join();
}

void RosIngest::run() {
  while (!stop_.triggered()) {
    // A short timeout: frames waiting for colour or tf must time out even when nothing arrives.
    if (auto woke = waitset_.wait(DDS_MSECS(20)); !woke) {
      state_.errors.record("ros-ingest", woke.error());
      continue;
    }
    takeAll();
    flush();
  }
}

void RosIngest::takeAll() {
  // tf and CameraInfo first, so the images of this batch can use them.
  auto drain = [](auto& input, auto&& fn) {
    if (!input) return;
    for (;;) {
      auto n = input->reader.takeLoaned(16, [&](const auto& msg, const dds_sample_info_t&) { fn(msg); });
      if (!n.ok() || n.value() == 0) break;
    }
  };
  drain(tf_static_in_, [this](const tf2_msgs_msg_dds__TFMessage_& m) { onTf(m, true); });
  drain(tf_in_, [this](const tf2_msgs_msg_dds__TFMessage_& m) { onTf(m, false); });
  drain(camera_info_, [this](const sensor_msgs_msg_dds__CameraInfo_& m) { onCameraInfo(m); });
  drain(color_, [this](const sensor_msgs_msg_dds__Image_& m) { onColor(m); });
  drain(compressed_color_, [this](const sensor_msgs_msg_dds__CompressedImage_& m) { onCompressedColor(m); });
  drain(depth_, [this](const sensor_msgs_msg_dds__Image_& m) { onDepth(m); });
  drain(compressed_depth_, [this](const sensor_msgs_msg_dds__CompressedImage_& m) { onCompressedDepth(m); });
}

// A ROS frame arrives as two images, each decoded as it comes: each is a run of the frame decode
// stage (a JPEG colour image is most of a frame's decode).
void RosIngest::onDepth(const sensor_msgs_msg_dds__Image_& msg) {
  addDepth(
      msg.header, [&] { return wire::depthImageToMetres(msg); }, "ROS depth image ");
}

void RosIngest::onCompressedDepth(const sensor_msgs_msg_dds__CompressedImage_& msg) {
  addDepth(
      msg.header, [&] { return wire::compressedDepthToMetres(msg); }, "ROS compressed depth image ");
}

void RosIngest::addDepth(const std_msgs_msg_dds__Header_& header, const std::function<Result<cv::Mat>()>& decode,
                         const char* what) {
  const uint64_t seq = next_seq_++;
  ++state_.frames_received;
  state_.frameArrived(config_.camera_id, seq);
  const auto start = std::chrono::steady_clock::now();
  Result<cv::Mat> depth = decode();
  state_.stages.recordSince(Stage::kFrameDecode, start);
  if (!depth.ok()) {
    state_.reject(reason::kInvalidFrame, config_.camera_id, what + std::to_string(seq), depth.error());
    return;
  }
  if (auto dropped = assembler_.addDepth(seq, wire::stampOf(header), text(header.frame_id), std::move(depth).value(),
                                         RosFrameAssembler::Clock::now())) {
    count(*dropped);
  }
}

void RosIngest::onColor(const sensor_msgs_msg_dds__Image_& msg) {
  const auto start = std::chrono::steady_clock::now();
  auto image = wire::imageToMat(msg);
  state_.stages.recordSince(Stage::kFrameDecode, start);
  if (image.ok() && image.value().type() != CV_8UC3) {
    image = makeError("colour image: encoding " + text(msg.encoding) + " is not a colour encoding (rgb8, bgr8)");
  }
  if (!image.ok()) {
    state_.reject(reason::kInvalidFrame, config_.camera_id, "ROS colour image", image.error());
    return;
  }
  if (auto dropped = assembler_.addColor(wire::stampOf(msg.header), std::move(image).value())) count(*dropped);
}

void RosIngest::onCompressedColor(const sensor_msgs_msg_dds__CompressedImage_& msg) {
  const auto start = std::chrono::steady_clock::now();
  auto image = wire::compressedImageToMat(msg);
  state_.stages.recordSince(Stage::kFrameDecode, start);
  if (image.ok() && image.value().type() != CV_8UC3) {
    image = makeError("compressed colour image: format '" + text(msg.format) + "' did not decode to colour");
  }
  if (!image.ok()) {
    state_.reject(reason::kInvalidFrame, config_.camera_id, "ROS compressed colour image", image.error());
    return;
  }
  if (auto dropped = assembler_.addColor(wire::stampOf(msg.header), std::move(image).value())) count(*dropped);
}

void RosIngest::onCameraInfo(const sensor_msgs_msg_dds__CameraInfo_& msg) {
  auto intrinsics = wire::intrinsicsFromCameraInfo(msg);
  if (!intrinsics.ok()) {
    state_.reject(reason::kInvalidFrame, config_.camera_id, "ROS CameraInfo", intrinsics.error());
    return;
  }
  assembler_.setIntrinsics(intrinsics.value());
}

void RosIngest::onTf(const tf2_msgs_msg_dds__TFMessage_& msg, bool is_static) {
  for (uint32_t i = 0; i < msg.transforms._length; ++i) {
    const auto& t = msg.transforms._buffer[i];
    const std::string parent = text(t.header.frame_id), child = text(t.child_frame_id);
    auto pose = wire::poseFromTransform(t.transform);
    Status added = pose.ok() ? tf_.add(parent, child, pose.value(), wire::stampOf(t.header), is_static)
                             : Status(makeError(pose.error()));
    if (!added) {
      state_.reject("invalid_transform", config_.camera_id, "tf " + parent + " -> " + child, added.error());
    }
  }
}

void RosIngest::flush() {
  std::vector<Frame> ready;
  std::vector<RosFrameAssembler::Drop> drops;
  const auto lookup = [this](const std::string& camera_frame, Stamp stamp) {
    return tf_.lookup(config_.world_frame, camera_frame, stamp);
  };
  assembler_.poll(RosFrameAssembler::Clock::now(), lookup, ready, drops);
  for (const auto& drop : drops) count(drop);
  for (Frame& frame : ready) {
    if (config_.use_tf && !frame.camera_to_world && !warned_tf_gap_) {
      spdlog::warn("camera {}: no tf {} -> {} for frame {}: tracking it from the last pose (warned once)",
                   frame.camera_id, config_.world_frame, frame.frame_id, frame.seq);
      warned_tf_gap_ = true;
    }
    if (auto evicted = frames_.push(std::move(frame))) {
      state_.dropped.add(reason::kQueueFull, evicted->camera_id);
    }
    state_.touch();
  }
}

void RosIngest::count(const RosFrameAssembler::Drop& drop) {
  const std::string source = drop.seq ? "ROS frame " + std::to_string(drop.seq) : "ROS colour image";
  if (drop.rejected) {
    state_.reject(drop.reason, config_.camera_id, source, drop.message);
  } else {
    state_.dropped.add(drop.reason, config_.camera_id);
    spdlog::debug("camera {}: dropped {}: {}", config_.camera_id, source, drop.message);
    state_.touch();
  }
}

void RosIngest::publishPose(const Frame& frame, const TrackOutcome& outcome) {
  if (!outcome.posed() || config_.publish_tf == "none") return;
  if (config_.publish_tf == "tracked" && outcome.pose_state == PoseState::kGiven) return;
  const std::string child = !config_.tf_child_frame.empty() ? config_.tf_child_frame
                            : !frame.frame_id.empty()       ? frame.frame_id
                                                            : frame.camera_id;
  auto transform = wire::transformFromPose(outcome.camera_to_world, frame.stamp, config_.world_frame, child);
  tf2_msgs_msg_dds__TFMessage_ msg{};
  msg.transforms._buffer = &transform.msg();
  msg.transforms._length = msg.transforms._maximum = 1;
  msg.transforms._release = false;
  std::lock_guard lock(tf_writer_mutex_);
  if (Status ok = tf_writer_.write(msg); !ok) spdlog::debug("tf: {}", ok.error());
}

}  // namespace semfuse::server
