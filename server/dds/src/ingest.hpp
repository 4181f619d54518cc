#pragma once
// Ingest: the DDS side of the input. One thread waits on the frames and segmentations readers,
// takes samples on loan, decodes and validates them, and hands them over (frames to the
// per-camera queue, segmentations to the fusion loop). Nothing heavy happens here, and every
// sample either moves on or is counted as rejected with its reason and a precise message.
#include <atomic>
#include <thread>

#include "frame_queue.hpp"
#include "fusion_loop.hpp"
#include "msg.h"
#include "semfuse/core/legend.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/waitset.hpp"
#include "server_state.hpp"

namespace semfuse::server {

class Ingest {
 public:
  Ingest(const dds::Participant& participant, FrameQueue& frames, FusionLoop& fusion, ServerState& state,
         const LabelLegend& legend);
  ~Ingest();

  void start();
  void stop();

 private:
  void run();
  void onFrame(const semfuse_msg_dds__Frame_& msg);
  void onSegmentation(const semfuse_msg_dds__Segmentation_& msg);

  FrameQueue& frames_;
  FusionLoop& fusion_;
  ServerState& state_;
  const LabelLegend& legend_;

  dds::Topic<semfuse_msg_dds__Frame_> frame_topic_;
  dds::Topic<semfuse_msg_dds__Segmentation_> segmentation_topic_;
  dds::Reader<semfuse_msg_dds__Frame_> frame_reader_;
  dds::Reader<semfuse_msg_dds__Segmentation_> segmentation_reader_;
  dds::ReadCondition frames_ready_;
  dds::ReadCondition segmentations_ready_;
  dds::GuardCondition stop_;
  dds::WaitSet waitset_;
  std::thread thread_;
};

}  // namespace semfuse::server
