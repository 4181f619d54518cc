#include "occupancy_publisher.hpp"

#include <spdlog/spdlog.h>

#include "distance_handlers.hpp"
#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {

OccupancyPublisher::OccupancyPublisher(const dds::Participant& participant, const DistanceField& field,
                                       const EsdfConfig& config)
    : field_(field),
      config_(config),
      topic_(participant, dds::topics::kOccupancy),
      writer_(topic_, dds::qos::occupancy()) {}

OccupancyPublisher::~OccupancyPublisher() { stop(); }

void OccupancyPublisher::start() {
  if (!(config_.occupancy_rate_hz > 0.0)) return;
  {
    std::lock_guard lock(mutex_);
    running_ = true;
  }
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-occupancy");
    lowerToQueryPriority();
    nameTbbWorkers();
    run();
  });
}

void OccupancyPublisher::stop() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void OccupancyPublisher::run() {
  const auto period = std::chrono::duration<double>(1.0 / config_.occupancy_rate_hz);
  uint64_t published_revision = ~0ull;
  std::unique_lock lock(mutex_);
  while (running_) {
    wake_.wait_for(lock, period, [this] { return !running_; });
    if (!running_) break;
    const uint64_t revision = field_.stats().revision;
    if (revision == published_revision || revision == 0) continue;
    lock.unlock();
    OccupancyGrid grid = publishedOccupancyGrid(field_, config_);
    grid.stamp = wire::stampNow();
    dds::Sample<nav_msgs_msg_dds__OccupancyGrid_> sample;
    wire::fillOccupancyGrid(*sample, grid);
    if (Status ok = writer_.write(*sample); !ok) spdlog::debug("occupancy: {}", ok.error());
    else ++published_;
    published_revision = revision;
    lock.lock();
  }
}

}  // namespace semfuse::server
