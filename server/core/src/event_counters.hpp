#pragma once
// Counters keyed by (reason, camera) for everything the server drops or rejects, and a bounded
// log of the most recent errors. Nothing accepted is ever lost silently: each path that gives up
// on an input bumps one of these, and both end up in the published ServerStatus.
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace semfuse::server {

struct CounterEntry {
  std::string reason;
  std::string camera_id;
  uint64_t count = 0;
};

class EventCounters {
 public:
  void add(const std::string& reason, const std::string& camera_id, uint64_t n = 1);
  uint64_t get(const std::string& reason, const std::string& camera_id) const;
  std::vector<CounterEntry> snapshot() const;  // sorted by reason, then camera

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, uint64_t> counts_;
};

struct ErrorRecord {
  std::chrono::system_clock::time_point time;
  std::string source;
  std::string message;
};

// The last `capacity` errors, newest last.
class ErrorLog {
 public:
  explicit ErrorLog(size_t capacity = 16) : capacity_(capacity) {}
  void record(std::string source, std::string message);
  std::vector<ErrorRecord> snapshot() const;

 private:
  mutable std::mutex mutex_;
  size_t capacity_;
  std::deque<ErrorRecord> records_;
};

}  // namespace semfuse::server
