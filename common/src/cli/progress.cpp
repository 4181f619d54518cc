#include "semfuse/cli/progress.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include <spdlog/spdlog.h>

namespace semfuse::cli {

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  const auto s = static_cast<long>(std::lround(seconds));
  char text[32];
  if (s >= 3600) std::snprintf(text, sizeof text, "%ldh%02ldm", s / 3600, (s / 60) % 60);
  else if (s >= 60) std::snprintf(text, sizeof text, "%ldm%02lds", s / 60, s % 60);
  else std::snprintf(text, sizeof text, "%lds", s);
  return text;
}

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      terminal_(isatty(STDOUT_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

Progress::~Progress() { finish(); }

double Progress::rate() const {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return elapsed > 0 ? done_ / elapsed : 0.0;
}

void Progress::update(std::size_t done) {
  done_ = done;
  const auto now = std::chrono::steady_clock::now();
  // Redraw at 10 Hz on a terminal; log every 5 s otherwise.
  const auto period = terminal_ ? std::chrono::milliseconds(100) : std::chrono::milliseconds(5000);
  if (now - last_draw_ < period && done != total_) return;
  last_draw_ = now;
  if (terminal_) {
    drawBar(done);
  } else if (total_ > 0) {
    spdlog::info("{}: {}/{} frames, {:.1f} frames/s, ETA {}", label_, done, total_, rate(),
                 formatDuration(rate() > 0 ? (total_ - done) / rate() : NAN));
  } else {
    spdlog::info("{}: {} frames, {:.1f} frames/s", label_, done, rate());
  }
}

void Progress::drawBar(std::size_t done) {
  constexpr int kWidth = 30;
  if (total_ == 0) {
    std::printf("\r%s %zu frames  %.1f frames/s   ", label_.c_str(), done, rate());
  } else {
    const double fraction = std::min(1.0, static_cast<double>(done) / total_);
    const int filled = static_cast<int>(fraction * kWidth);
    const std::string bar = std::string(filled, '#') + std::string(kWidth - filled, '.');
    const double eta = rate() > 0 ? (total_ - done) / rate() : NAN;
    std::printf("\r%s [%s] %zu/%zu  %.1f frames/s  ETA %s   ", label_.c_str(), bar.c_str(), done, total_, rate(),
                formatDuration(eta).c_str());
  }
  std::fflush(stdout);
}

void Progress::finish() {
  if (finished_) return;
  finished_ = true;
  if (terminal_) {
    drawBar(done_);
    std::printf("\n");
    std::fflush(stdout);
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  spdlog::info("{}: {} frames in {} ({:.1f} frames/s)", label_, done_, formatDuration(elapsed), rate());
}

}  // namespace semfuse::cli
