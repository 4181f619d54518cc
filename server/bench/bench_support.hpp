#pragma once
// Helpers shared by the bench files: where the shared data lives, timing statistics, peak RSS,
// and a plain aligned table so that every subcommand prints figures the same way.
#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace semfuse::bench {

// ../shared beside the source tree, or $SEMFUSE_SHARED.
std::filesystem::path sharedDir();
inline std::filesystem::path redkitchenDir() { return sharedDir() / "data" / "7scenes-redkitchen"; }

// Milliseconds of repeated runs; median and 95th percentile by nearest rank.
class Timings {
 public:
  void add(double ms) { samples_.push_back(ms); }
  std::size_t count() const { return samples_.size(); }
  double median() const { return percentile(50); }
  double p95() const { return percentile(95); }
  double mean() const;
  double percentile(double p) const;

 private:
  std::vector<double> samples_;
};

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double elapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// CPU time of the whole process (all threads): on a machine shared with other work, wall-clock
// timings grow with the load while CPU time stays close to the code's own cost.
class CpuStopwatch {
 public:
  CpuStopwatch() : start_(now()) {}
  double elapsedMs() const { return now() - start_; }

 private:
  static double now();
  double start_;
};

// Peak resident set size of this process so far, MiB.
double peakRssMiB();

// The 1-minute load average: timings on a shared machine mean little without it.
double loadAverage();

// Rows of (what, value, note), printed with aligned columns.
class Table {
 public:
  explicit Table(std::string title) : title_(std::move(title)) {}
  void add(std::string what, std::string value, std::string note = {});
  void addMs(const std::string& what, const Timings& timings, std::string note = {});  // "median / p95"
  void print() const;

 private:
  std::string title_;
  std::vector<std::vector<std::string>> rows_;
};

std::string formatNumber(double value, int decimals = 2);

}  // namespace semfuse::bench
