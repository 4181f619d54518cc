#pragma once
// /proc readings of the server: CPU seconds of the process and of each thread, resident memory.
#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <map>
#include <string>
#include <thread>
#include <vector>

namespace semfuse::bench::ingest {

struct ThreadCpu {
  std::string name;
  double seconds = 0;
};

struct CpuSample {
  std::chrono::steady_clock::time_point when = std::chrono::steady_clock::now();
  double process_s = 0;
  std::map<int, ThreadCpu> threads;  // by tid
};

CpuSample sampleCpu(pid_t pid);

// The process's CPU between two of its samples, 100 % = 1 core (0 over an empty window).
double processPercent(const CpuSample& start, const CpuSample& end);

// The CPU of the threads of one name between two samples (a TBB pool's workers share a name).
struct ThreadCpuShare {
  std::string name;
  int threads = 0;     // threads of this name
  double percent = 0;  // 100 % = 1 core, summed over them
};
// Busiest first.
std::vector<ThreadCpuShare> threadShares(const CpuSample& start, const CpuSample& end);

// A field of /proc/<pid>/status in MiB ("VmRSS:", "VmHWM:"), 0 when unreadable.
double procStatusMiB(pid_t pid, const std::string& field);

// Samples VmRSS every 100 ms: the peak during one run, which VmHWM (peak since start) cannot give.
class RssMonitor {
 public:
  explicit RssMonitor(pid_t pid) : pid_(pid), thread_([this] { loop(); }) {}
  ~RssMonitor() {
    running_ = false;
    thread_.join();
  }
  void resetPeak() { peak_ = procStatusMiB(pid_, "VmRSS:"); }
  double peak() const { return peak_; }

 private:
  void loop();

  pid_t pid_;
  std::atomic<double> peak_{0};
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace semfuse::bench::ingest
