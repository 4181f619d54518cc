#include "periodic_thread.hpp"

#include <algorithm>
#include <exception>
#include <utility>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {

using Clock = std::chrono::steady_clock;

void PeriodicThread::start(std::string name, Clock::duration period, std::function<void()> round) {
  stop();
  name_ = std::move(name);
  round_ = std::move(round);
  {
    std::lock_guard lock(mutex_);
    running_ = true;
  }
  thread_ = std::thread([this, period] {
    setCurrentThreadName(name_);
    lowerToQueryPriority();
    nameTbbWorkers();
    run(period);
  });
}

void PeriodicThread::stop() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void PeriodicThread::run(Clock::duration period) {
  auto next = Clock::now() + period;
  std::unique_lock lock(mutex_);
  while (running_) {
    wake_.wait_until(lock, next, [this] { return !running_; });
    if (!running_) break;
    lock.unlock();
    try {
      round_();
    } catch (const std::exception& e) {
      spdlog::error("{}: {}", name_, e.what());
    }
    next = std::max(next + period, Clock::now());
    lock.lock();
  }
}

}  // namespace semfuse::server
