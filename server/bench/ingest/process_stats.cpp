#include "process_stats.hpp"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

namespace semfuse::bench::ingest {
namespace {

// utime + stime of a /proc/.../stat line, and the comm name. The name is in parentheses and may
// contain spaces, so fields are counted from the last ')'.
std::optional<ThreadCpu> readStat(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return std::nullopt;
  const auto open = line.find('('), close = line.rfind(')');
  if (open == std::string::npos || close == std::string::npos) return std::nullopt;
  std::istringstream fields(line.substr(close + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; fields >> field; ++i) {  // the first field after ')' is field 3 (state)
    if (i == 14) utime = std::stod(field);
    if (i == 15) {
      stime = std::stod(field);
      break;
    }
  }
  static const double ticks = static_cast<double>(::sysconf(_SC_CLK_TCK));
  return ThreadCpu{line.substr(open + 1, close - open - 1), (utime + stime) / ticks};
}

}  // namespace

CpuSample sampleCpu(pid_t pid) {
  CpuSample sample;
  const std::string base = "/proc/" + std::to_string(pid);
  if (auto process = readStat(base + "/stat")) sample.process_s = process->seconds;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(base + "/task", ec)) {
    if (auto thread = readStat(entry.path().string() + "/stat"))
      sample.threads[std::stoi(entry.path().filename().string())] = *thread;
  }
  return sample;
}

double procStatusMiB(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(field.size())) / 1024.0;  // kB
  }
  return 0;
}

void RssMonitor::loop() {
  while (running_) {
    const double now = procStatusMiB(pid_, "VmRSS:");
    double seen = peak_;
    while (now > seen && !peak_.compare_exchange_weak(seen, now)) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

double processPercent(const CpuSample& start, const CpuSample& end) {
  const double window_s = std::chrono::duration<double>(end.when - start.when).count();
  return window_s > 0 ? (end.process_s - start.process_s) / window_s * 100.0 : 0.0;
}

std::vector<ThreadCpuShare> threadShares(const CpuSample& start, const CpuSample& end) {
  const double window_s = std::chrono::duration<double>(end.when - start.when).count();
  if (!(window_s > 0)) return {};
  std::map<std::string, ThreadCpuShare> by_name;
  for (const auto& [tid, thread] : end.threads) {
    const auto was = start.threads.find(tid);
    const double used = thread.seconds - (was == start.threads.end() ? 0.0 : was->second.seconds);
    ThreadCpuShare& share = by_name[thread.name];
    share.name = thread.name;
    ++share.threads;
    share.percent += used / window_s * 100.0;
  }
  std::vector<ThreadCpuShare> shares;
  for (auto& [name, share] : by_name) shares.push_back(std::move(share));
  std::sort(shares.begin(), shares.end(), [](const auto& a, const auto& b) { return a.percent > b.percent; });
  return shares;
}

}  // namespace semfuse::bench::ingest
