#include "rss_timeline.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "ingest/process_stats.hpp"

namespace semfuse::bench::load {
namespace {

// Slope of y over t in units per minute, least squares; 0 with fewer than two samples.
template <class Value>
double slopePerMinute(const std::vector<RssSample>& samples, Value value) {
  if (samples.size() < 2) return 0;
  double mt = 0, my = 0;
  for (const auto& s : samples) {
    mt += s.t_s;
    my += value(s);
  }
  mt /= samples.size();
  my /= samples.size();
  double num = 0, den = 0;
  for (const auto& s : samples) {
    num += (s.t_s - mt) * (value(s) - my);
    den += (s.t_s - mt) * (s.t_s - mt);
  }
  return den > 0 ? num / den * 60.0 : 0;
}

}  // namespace

RssTimeline::RssTimeline(pid_t pid, std::function<MapMiB()> map_mib)
    : pid_(pid), map_mib_(std::move(map_mib)), thread_([this] { loop(); }) {}

RssTimeline::~RssTimeline() {
  running_ = false;
  thread_.join();
}

void RssTimeline::loop() {
  const auto start = std::chrono::steady_clock::now();
  for (auto next = start; running_; next += std::chrono::seconds(1)) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const MapMiB map = map_mib_();
    RssSample sample{t, ingest::procStatusMiB(pid_, "VmRSS:"), map.map, map.copies};
    {
      std::lock_guard lock(mutex_);
      samples_.push_back(sample);
    }
    // Short sleeps, so that the destructor does not wait out a whole second.
    while (running_ && std::chrono::steady_clock::now() < next + std::chrono::seconds(1))
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

std::vector<RssSample> RssTimeline::samples() {
  std::lock_guard lock(mutex_);
  return samples_;
}

RssSummary RssTimeline::summary() {
  const std::vector<RssSample> all = samples();
  RssSummary s;
  s.samples = all.size();
  if (all.empty()) return s;
  s.start_mib = all.front().rss_mib;
  s.end_mib = all.back().rss_mib;
  s.map_start_mib = all.front().map_mib;
  s.map_end_mib = all.back().map_mib;
  s.copies_start_mib = all.front().copies_mib;
  s.copies_end_mib = all.back().copies_mib;
  for (const auto& sample : all) s.max_mib = std::max(s.max_mib, sample.rss_mib);
  s.slope_mib_per_min = slopePerMinute(all, [](const RssSample& x) { return x.rss_mib; });
  s.non_map_slope_mib_per_min = slopePerMinute(all, [](const RssSample& x) { return x.nonMapMiB(); });
  const std::vector<RssSample> late(all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2), all.end());
  s.late_slope_mib_per_min = slopePerMinute(late, [](const RssSample& x) { return x.rss_mib; });
  s.late_non_map_slope_mib_per_min = slopePerMinute(late, [](const RssSample& x) { return x.nonMapMiB(); });
  return s;
}

}  // namespace semfuse::bench::load
