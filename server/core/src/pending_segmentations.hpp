#pragma once
// Segmentations that arrived before their frame was fused. They wait here, bounded in number
// and in time, until the fusion thread has integrated the frame they belong to.
#include <chrono>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "semfuse/core/types.hpp"

namespace semfuse::server {

class PendingSegmentations {
 public:
  using Clock = std::chrono::steady_clock;

  PendingSegmentations(size_t capacity, std::chrono::milliseconds timeout) : capacity_(capacity), timeout_(timeout) {}

  // Adds one; returns the segmentation evicted because the set was full, if any.
  std::vector<Segmentation> add(Segmentation segmentation, Clock::time_point now = Clock::now());

  // Removes and returns every segmentation waiting for (camera, seq).
  std::vector<Segmentation> takeFor(const std::string& camera_id, uint64_t seq);

  // Removes and returns every segmentation waiting for a frame of `camera_id` before `seq`: a
  // camera's frames are fused in order, so once `seq` is fused those frames will not come.
  std::vector<Segmentation> takeBefore(const std::string& camera_id, uint64_t seq);

  // Removes and returns those that waited longer than the timeout.
  std::vector<Segmentation> expire(Clock::time_point now = Clock::now());

  size_t size() const { return waiting_.size(); }
  void clear() { waiting_.clear(); }

 private:
  // Removes and returns, in arrival order, those for which `matches(segmentation)` holds.
  template <class Matches>
  std::vector<Segmentation> takeIf(Matches matches);

  struct Waiting {
    Segmentation segmentation;
    Clock::time_point arrived;
  };
  size_t capacity_;
  std::chrono::milliseconds timeout_;
  std::deque<Waiting> waiting_;  // arrival order
};

}  // namespace semfuse::server
