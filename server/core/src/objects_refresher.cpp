#include "objects_refresher.hpp"

#include <algorithm>
#include <exception>
#include <utility>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {

using Clock = std::chrono::steady_clock;

ObjectsRefresher::ObjectsRefresher(const MapAccess& map, objects::ObjectTracker& tracker, double rate_hz,
                                   std::function<bool()> listening)
    : map_(map), tracker_(tracker), listening_(std::move(listening)) {
  if (!(rate_hz > 0.0)) return;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / rate_hz));
  thread_ = std::thread([this, period] {
    setCurrentThreadName("sf-objects");
    lowerToQueryPriority();
    nameTbbWorkers();
    run(period);
  });
}

ObjectsRefresher::~ObjectsRefresher() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool ObjectsRefresher::wanted() const {
  if (listening_ && listening_()) return true;
  const Clock::rep touched = touched_at_.load();
  return touched != 0 && Clock::now() - Clock::time_point(Clock::duration(touched)) < kIdleAfter;
}

void ObjectsRefresher::run(Clock::duration period) {
  auto next = Clock::now() + period;
  std::unique_lock lock(mutex_);
  while (running_) {
    wake_.wait_until(lock, next, [this] { return !running_; });
    if (!running_) break;
    lock.unlock();
    try {
      if (wanted()) tracker_.objectsOf(map_.snapshot());  // the same map again returns at once
    } catch (const std::exception& e) {
      spdlog::error("objects refresh: {}", e.what());
    }
    // A fixed schedule; an update that overran starts the next one at once, not a burst.
    next = std::max(next + period, Clock::now());
    lock.lock();
  }
}

}  // namespace semfuse::server
