#include "semfuse/client/occupancy_listener.hpp"

#include <atomic>
#include <mutex>

#include <nav_msgs.h>

#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/wire/distance_codecs.hpp"

namespace semfuse::client {

struct OccupancyListener::Impl {
  explicit Impl(const dds::Participant& p)
      : topic(p, dds::topics::kOccupancy), reader(topic, dds::qos::occupancy()), ready(reader.handle()), waitset(p) {
    waitset.attach(ready.handle());
  }

  // Takes what arrived; true when a new grid came.
  bool poll() {
    std::lock_guard lock(mutex);
    bool fresh = false;
    while (auto sample = reader.take()) {
      if (auto grid = wire::decodeOccupancyGrid(**sample)) {
        latest = std::move(grid).value();
        ++received;
        fresh = true;
      } else {
        ++rejected;
      }
    }
    return fresh;
  }

  dds::Topic<nav_msgs_msg_dds__OccupancyGrid_> topic;
  dds::Reader<nav_msgs_msg_dds__OccupancyGrid_> reader;
  dds::ReadCondition ready;
  dds::WaitSet waitset;
  std::mutex mutex;
  std::optional<OccupancyGrid> latest;
  std::atomic<uint64_t> received{0}, rejected{0};
  bool handed_out = false;  // the latest grid was returned by waitForGrid
};

OccupancyListener::OccupancyListener(const dds::Participant& participant)
    : impl_(std::make_unique<Impl>(participant)) {}
OccupancyListener::~OccupancyListener() = default;

std::optional<OccupancyGrid> OccupancyListener::latest() {
  impl_->poll();
  std::lock_guard lock(impl_->mutex);
  return impl_->latest;
}

std::optional<OccupancyGrid> OccupancyListener::waitForGrid(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (impl_->poll()) impl_->handed_out = false;
    {
      std::lock_guard lock(impl_->mutex);
      if (impl_->latest && !impl_->handed_out) {
        impl_->handed_out = true;
        return impl_->latest;
      }
    }
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    static_cast<void>(impl_->waitset.wait(DDS_MSECS(left.count())));
  }
}

uint64_t OccupancyListener::received() const { return impl_->received.load(); }
uint64_t OccupancyListener::rejected() const { return impl_->rejected.load(); }

}  // namespace semfuse::client
