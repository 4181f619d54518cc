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

// A frame's pose received -> the first update received after it that holds more integrated
// frames than the one before the pose: how stale a follower's map is behind the camera (the pose
// comes before its frame's integration, and a frame integration skipped is followed by a newer).
Timings updateLatencies(const std::vector<PoseRecord>& poses, const std::vector<UpdateArrival>& arrivals);

}  // namespace semfuse::bench::ingest
