#include "event_counters.hpp"

namespace semfuse::server {

void EventCounters::add(const std::string& reason, const std::string& camera_id, uint64_t n) {
  std::lock_guard lock(mutex_);
  counts_[{reason, camera_id}] += n;
}

uint64_t EventCounters::get(const std::string& reason, const std::string& camera_id) const {
  std::lock_guard lock(mutex_);
  auto it = counts_.find({reason, camera_id});
  return it == counts_.end() ? 0 : it->second;
}

std::vector<CounterEntry> EventCounters::snapshot() const {
  std::lock_guard lock(mutex_);
  std::vector<CounterEntry> out;
  out.reserve(counts_.size());
  for (const auto& [key, count] : counts_) out.push_back({key.first, key.second, count});
  return out;
}

void ErrorLog::record(std::string source, std::string message) {
  std::lock_guard lock(mutex_);
  records_.push_back({std::chrono::system_clock::now(), std::move(source), std::move(message)});
  while (records_.size() > capacity_) records_.pop_front();
}

std::vector<ErrorRecord> ErrorLog::snapshot() const {
  std::lock_guard lock(mutex_);
  return {records_.begin(), records_.end()};
}

}  // namespace semfuse::server
