#pragma once
// Every TrackedPose the server publishes, with the latency from its frame's publish time (the
// publish time travels in the frame's header stamp, which the server echoes in the pose).
#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "msg.h"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/waitset.hpp"

namespace semfuse::bench::ingest {

struct PoseRecord {
  std::string camera_id;
  bool posed = false;  // false: tracking lost
  double latency_ms = 0;
  double track_ms = 0;     // the tracking thread's work on the frame
  double received_ms = 0;  // system clock when it arrived
};

class PoseCollector {
 public:
  using PoseMsg = semfuse_msg_dds__TrackedPose_;

  explicit PoseCollector(const dds::Participant& participant);
  ~PoseCollector();
  // The poses received since the last call.
  std::vector<PoseRecord> take();

 private:
  void loop();

  dds::Topic<PoseMsg> topic_;
  dds::Reader<PoseMsg> reader_;
  dds::ReadCondition ready_;
  dds::WaitSet waitset_;
  std::mutex mutex_;
  std::vector<PoseRecord> records_;
  std::atomic<bool> running_{true};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace semfuse::bench::ingest
