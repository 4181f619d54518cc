#include "followed_updates.hpp"

#include <algorithm>
#include <chrono>

namespace semfuse::bench::ingest {

FollowedUpdates::FollowedUpdates(const dds::Participant& participant) : follower_(participant) {
  follower_.setListener([this](const client::MapFollowerChange& change) {
    if (change.source != client::MapFollowerChange::Source::kUpdate) return;
    const double now_ms =
        std::chrono::duration<double, std::milli>(std::chrono::system_clock::now().time_since_epoch()).count();
    std::lock_guard lock(mutex_);
    arrivals_.push_back({now_ms, change.state->header.frames_integrated});
  });
  follower_.start();
}

void FollowedUpdates::clear() {
  std::lock_guard lock(mutex_);
  arrivals_.clear();
}

std::vector<UpdateArrival> FollowedUpdates::arrivals() {
  std::lock_guard lock(mutex_);
  return arrivals_;
}

Timings updateLatencies(const std::vector<PoseRecord>& poses, const std::vector<UpdateArrival>& arrivals) {
  std::vector<double> integrated_at;
  for (const PoseRecord& p : poses)
    if (p.integrated) integrated_at.push_back(p.received_ms);
  std::sort(integrated_at.begin(), integrated_at.end());
  Timings latency;
  std::size_t u = 0;
  for (std::size_t i = 0; i < integrated_at.size(); ++i) {
    while (u < arrivals.size() && arrivals[u].frames_integrated < i + 1) ++u;
    if (u == arrivals.size()) break;
    latency.add(std::max(0.0, arrivals[u].received_ms - integrated_at[i]));
  }
  return latency;
}

}  // namespace semfuse::bench::ingest
