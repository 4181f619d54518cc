#include "stage_timings.hpp"

#include <algorithm>

#include "semfuse/core/percentile.hpp"

namespace semfuse::server {

const char* stageName(Stage stage) {
  switch (stage) {
    case Stage::kFrameDecode:
      return "frame_decode";
    case Stage::kFrameQueue:
      return "frame_queue";
    case Stage::kTrack:
      return "track";
    case Stage::kIntegrationQueue:
      return "integration_queue";
    case Stage::kIntegrate:
      return "integrate";
    case Stage::kLateLabels:
      return "late_labels";
    case Stage::kMapUpdate:
      return "map_update";
    case Stage::kDistanceField:
      return "distance_field";
    case Stage::kCount:
      break;
  }
  return "unknown";
}

void StageTimings::record(Stage stage, double ms) {
  if (stage == Stage::kCount || !std::isfinite(ms)) return;
  std::lock_guard lock(mutex_);
  Samples& samples = stages_[static_cast<std::size_t>(stage)];
  const auto value = static_cast<float>(std::max(0.0, ms));
  if (samples.recent.size() < kWindow) samples.recent.push_back(value);
  else samples.recent[samples.count % kWindow] = value;
  ++samples.count;
}

void StageTimings::recordSince(Stage stage, std::chrono::steady_clock::time_point start) {
  record(stage, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

std::vector<StageTiming> StageTimings::summary() const {
  std::vector<StageTiming> out;
  std::vector<float> sorted;
  std::lock_guard lock(mutex_);
  for (std::size_t i = 0; i < stages_.size(); ++i) {
    const Samples& samples = stages_[i];
    if (samples.count == 0) continue;
    sorted = samples.recent;
    std::sort(sorted.begin(), sorted.end());
    out.push_back({stageName(static_cast<Stage>(i)), samples.count, nearestRankPercentile(sorted, 50),
                   nearestRankPercentile(sorted, 95), sorted.back()});
  }
  return out;
}

}  // namespace semfuse::server
