#include "pose_collector.hpp"

#include <chrono>
#include <utility>

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/frame_codec.hpp"

namespace semfuse::bench::ingest {

PoseCollector::PoseCollector(const dds::Participant& participant)
    : topic_(participant, dds::topics::kPoses),
      reader_(topic_, dds::qos::poses()),
      ready_(reader_.handle()),
      waitset_(participant),
      thread_([this] { loop(); }) {}

PoseCollector::~PoseCollector() {
  running_ = false;
  thread_.join();
}

std::vector<PoseRecord> PoseCollector::take() {
  std::lock_guard lock(mutex_);
  return std::exchange(records_, {});
}

void PoseCollector::loop() {
  waitset_.attach(ready_.handle());
  while (running_) {
    if (auto woke = waitset_.wait(DDS_MSECS(100)); !woke || woke.value().empty()) continue;
    static_cast<void>(reader_.takeLoaned(dds::Reader<PoseMsg>::kMaxBatch, [this](const PoseMsg& pose, const auto&) {
      const double now_ms =
          std::chrono::duration<double, std::milli>(std::chrono::system_clock::now().time_since_epoch()).count();
      const double sent_ms = pose.header.stamp.sec * 1e3 + pose.header.stamp.nanosec * 1e-6;
      std::lock_guard lock(mutex_);
      records_.push_back({wire::stringOf(pose.camera_id), pose.posed, now_ms - sent_ms, pose.track_ms, now_ms});
    }));
  }
}

}  // namespace semfuse::bench::ingest
