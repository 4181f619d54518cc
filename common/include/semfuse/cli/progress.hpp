#pragma once
// Progress of a replay: a bar with frames/s and ETA redrawn in place on a terminal, or a plain
// log line every few seconds when stdout is a pipe or a file (a CI log must not fill with
// carriage returns).
#include <chrono>
#include <cstddef>
#include <string>

namespace semfuse::cli {

class Progress {
 public:
  // total 0 = unknown (a looping replay): no bar and no ETA, only the count and the rate.
  Progress(std::string label, std::size_t total);
  ~Progress();

  void update(std::size_t done);
  // Ends the bar line (terminal) or writes the final log line.
  void finish();

  // "12.3 frames/s"-style rate over the whole run so far.
  double rate() const;

 private:
  void drawBar(std::size_t done);

  std::string label_;
  std::size_t total_;
  bool terminal_;
  bool finished_ = false;
  std::size_t done_ = 0;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

// "1m05s", "12s".
std::string formatDuration(double seconds);

}  // namespace semfuse::cli
