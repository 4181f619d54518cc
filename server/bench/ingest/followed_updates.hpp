#pragma once
// A map follower (client::MapFollower, what a viewer runs) that notes when each live-mesh update
// arrives and how many frames the map it brings holds, so that a bench can tell how long an
// integrated frame takes to reach a follower's mesh.
#include <cstdint>
#include <mutex>
#include <vector>

#include "bench_support.hpp"
#include "pose_collector.hpp"
#include "semfuse/client/map_follower.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::bench::ingest {

struct UpdateArrival {
  double received_ms = 0;  // system clock, as PoseRecord::received_ms
  uint64_t frames_integrated = 0;
};

class FollowedUpdates {
 public:
  explicit FollowedUpdates(const dds::Participant& participant);
  void clear();
  std::vector<UpdateArrival> arrivals();
  client::MapFollowerStats followerStats() const { return follower_.stats(); }

 private:
  std::mutex mutex_;
  std::vector<UpdateArrival> arrivals_;
  client::MapFollower follower_;  // last: its listener writes the members above
};

// Frame integrated (its pose received) -> the first update received whose map includes it. The
// map must have been reset before the poses: then the i-th integrated frame is the map's i-th.
Timings updateLatencies(const std::vector<PoseRecord>& poses, const std::vector<UpdateArrival>& arrivals);

}  // namespace semfuse::bench::ingest
