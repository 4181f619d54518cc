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
  std::vector<double> posed_at;
  for (const PoseRecord& p : poses)
    if (p.posed) posed_at.push_back(p.received_ms);
  std::sort(posed_at.begin(), posed_at.end());
  Timings latency;
  std::size_t u = 0;
  uint64_t before = 0;  // frames integrated in the last update received before the pose
  for (double at : posed_at) {
    while (u < arrivals.size() && arrivals[u].received_ms < at) before = arrivals[u++].frames_integrated;
    std::size_t next = u;
    while (next < arrivals.size() && arrivals[next].frames_integrated <= before) ++next;
    if (next == arrivals.size()) break;
    latency.add(arrivals[next].received_ms - at);
  }
  return latency;
}

}  // namespace semfuse::bench::ingest
