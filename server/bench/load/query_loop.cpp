#include "query_loop.hpp"

#include <algorithm>
#include <utility>

namespace semfuse::bench::load {

QueryLoop::QueryLoop(const dds::Participant& participant, std::string name, double rate_hz, Query query)
    : client_(participant), query_(std::move(query)) {
  stats_.name = std::move(name);
  stats_.rate_hz = rate_hz;
}

QueryLoop::~QueryLoop() { stop(); }

void QueryLoop::start() {
  running_ = true;
  thread_ = std::thread([this] { loop(); });
}

void QueryLoop::stop() {
  running_ = false;
  if (thread_.joinable()) thread_.join();
}

QueryStats QueryLoop::stats() {
  std::lock_guard lock(mutex_);
  return stats_;
}

void QueryLoop::loop() {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / stats_.rate_hz));
  for (auto next = Clock::now(); running_; next += period) {
    std::this_thread::sleep_until(next);
    if (!running_) break;
    Stopwatch watch;
    const QueryOutcome outcome = query_(client_);
    const double ms = watch.elapsedMs();
    {
      std::lock_guard lock(mutex_);
      ++stats_.asked;
      switch (outcome.failure) {
        case client::Failure::kNone:
          ++stats_.answered;
          stats_.reply_ms.add(ms);
          break;
        case client::Failure::kServer:
          ++stats_.refused;
          break;
        case client::Failure::kTimeout:
          ++stats_.unanswered;
          break;
        case client::Failure::kClient:
          ++stats_.client_errors;
          break;
      }
      if (outcome.failure != client::Failure::kNone) stats_.last_error = outcome.error;
    }
    next = std::max(next, Clock::now() - period);
  }
}

}  // namespace semfuse::bench::load
