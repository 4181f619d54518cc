#include "ingest.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::server {
namespace {
std::string idOf(const char* camera, uint64_t seq) {
  return std::string(camera ? camera : "") + "/" + std::to_string(seq);
}
}  // namespace

Ingest::Ingest(const dds::Participant& participant, FrameQueue& frames, FusionLoop& fusion, ServerState& state,
               const LabelLegend& legend)
    : frames_(frames),
      fusion_(fusion),
      state_(state),
      legend_(legend),
      frame_topic_(participant, dds::topics::kFrames),
      segmentation_topic_(participant, dds::topics::kSegmentations),
      frame_reader_(frame_topic_, dds::qos::frameIngest()),
      segmentation_reader_(segmentation_topic_, dds::qos::segmentations()),
      frames_ready_(frame_reader_.handle()),
      segmentations_ready_(segmentation_reader_.handle()),
      stop_(participant),
      waitset_(participant) {
  waitset_.attach(frames_ready_.handle());
  waitset_.attach(segmentations_ready_.handle());
  waitset_.attach(stop_.handle());
}

Ingest::~Ingest() { stop(); }

void Ingest::start() {
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-ingest");
    run();
  });
}

void Ingest::stop() {
  if (!thread_.joinable()) return;
  stop_.trigger();
  thread_.join();
}

void Ingest::run() {
  while (!stop_.triggered()) {
    if (auto woke = waitset_.wait(DDS_MSECS(500)); !woke) {
      state_.errors.record("ingest", woke.error());
      continue;
    }
    // Segmentations first, and again after every batch of frames: they are cheap to take and may
    // be waited for by a frame in the same batch. Draining the frames before looking at the
    // segmentations again starved them while cameras kept the frames reader busy (decoding is
    // the slow part), and the segmentations reader's keep-last history then overwrote samples
    // that no counter saw.
    for (bool more = true; more && !stop_.triggered();) {
      auto segmentations = segmentation_reader_.takeLoaned(
          16, [this](const semfuse_msg_dds__Segmentation_& msg, const dds_sample_info_t&) { onSegmentation(msg); });
      auto frames = frame_reader_.takeLoaned(
          4, [this](const semfuse_msg_dds__Frame_& msg, const dds_sample_info_t&) { onFrame(msg); });
      more = (segmentations.ok() && segmentations.value() > 0) || (frames.ok() && frames.value() > 0);
    }
  }
}

void Ingest::onFrame(const semfuse_msg_dds__Frame_& msg) {
  ++state_.frames_received;
  const std::string camera = msg.camera_id ? msg.camera_id : "";
  state_.frameArrived(camera, msg.seq);
  const auto start = std::chrono::steady_clock::now();
  auto frame = wire::decodeFrame(msg);
  state_.stages.recordSince(Stage::kFrameDecode, start);
  if (!frame.ok()) {
    state_.reject(reason::kInvalidFrame, camera, "frame " + idOf(msg.camera_id, msg.seq), frame.error());
    return;
  }
  if (auto evicted = frames_.push(std::move(frame).value())) {
    state_.dropped.add(reason::kQueueFull, evicted->camera_id);
    spdlog::debug("camera {}: queue full, dropped frame {}", evicted->camera_id, evicted->seq);
    state_.touch();
  }
}

void Ingest::onSegmentation(const semfuse_msg_dds__Segmentation_& msg) {
  ++state_.segmentations_received;
  const std::string camera = msg.camera_id ? msg.camera_id : "";
  const std::string source = "segmentation " + std::string(msg.segmenter_id ? msg.segmenter_id : "") + " of " +
                             idOf(msg.camera_id, msg.frame_seq);
  auto segmentation = wire::decodeSegmentation(msg);
  if (!segmentation.ok()) {
    state_.reject(reason::kInvalidSegmentation, camera, source, segmentation.error());
    return;
  }
  if (Status labels_ok = wire::validateLabels(segmentation.value().labels, legend_); !labels_ok) {
    state_.reject(reason::kLabelOutOfLegend, camera, source, labels_ok.error());
    return;
  }
  fusion_.submitSegmentation(std::move(segmentation).value());
  state_.touch();
}

}  // namespace semfuse::server
