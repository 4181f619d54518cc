#include "bench_support.hpp"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>

#include "semfuse/core/percentile.hpp"

namespace semfuse::bench {

std::filesystem::path sharedDir() {
  if (const char* env = std::getenv("SEMFUSE_SHARED"); env && *env) return env;
  return std::filesystem::path(SEMFUSE_SOURCE_DIR) / ".." / "shared";
}

double Timings::mean() const {
  if (samples_.empty()) return 0;
  return std::accumulate(samples_.begin(), samples_.end(), 0.0) / static_cast<double>(samples_.size());
}

double Timings::percentile(double p) const {
  if (samples_.empty()) return 0;
  std::vector<double> sorted = samples_;
  std::sort(sorted.begin(), sorted.end());
  return nearestRankPercentile(sorted, p);
}

double CpuStopwatch::now() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

double peakRssMiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

double loadAverage() {
  double load = 0;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0;
    std::fclose(f);
  }
  return load;
}

std::string formatNumber(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

void Table::add(std::string what, std::string value, std::string note) {
  rows_.push_back({std::move(what), std::move(value), std::move(note)});
}

void Table::addMs(const std::string& what, const Timings& timings, std::string note) {
  add(what, formatNumber(timings.median()) + " / " + formatNumber(timings.p95()) + " ms", std::move(note));
}

void Table::print() const {
  std::size_t widths[3] = {0, 0, 0};
  for (const auto& row : rows_)
    for (std::size_t c = 0; c < 3; ++c) widths[c] = std::max(widths[c], row[c].size());
  std::printf("\n%s\n", title_.c_str());
  for (const auto& row : rows_)
    std::printf("  %-*s  %*s  %s\n", static_cast<int>(widths[0]), row[0].c_str(), static_cast<int>(widths[1]),
                row[1].c_str(), row[2].c_str());
  std::fflush(stdout);
}

}  // namespace semfuse::bench
