#include "pending_segmentations.hpp"

#include <utility>

namespace semfuse::server {

std::vector<Segmentation> PendingSegmentations::add(Segmentation segmentation, Clock::time_point now) {
  std::vector<Segmentation> evicted;
  while (capacity_ > 0 && waiting_.size() >= capacity_) {
    evicted.push_back(std::move(waiting_.front().segmentation));
    waiting_.pop_front();
  }
  waiting_.push_back({std::move(segmentation), now});
  return evicted;
}

std::vector<Segmentation> PendingSegmentations::takeFor(const std::string& camera_id, uint64_t seq) {
  std::vector<Segmentation> matched;
  for (auto it = waiting_.begin(); it != waiting_.end();) {
    if (it->segmentation.camera_id == camera_id && it->segmentation.frame_seq == seq) {
      matched.push_back(std::move(it->segmentation));
      it = waiting_.erase(it);
    } else {
      ++it;
    }
  }
  return matched;
}

std::vector<Segmentation> PendingSegmentations::takeBefore(const std::string& camera_id, uint64_t seq) {
  std::vector<Segmentation> orphaned;
  for (auto it = waiting_.begin(); it != waiting_.end();) {
    if (it->segmentation.camera_id == camera_id && it->segmentation.frame_seq < seq) {
      orphaned.push_back(std::move(it->segmentation));
      it = waiting_.erase(it);
    } else {
      ++it;
    }
  }
  return orphaned;
}

std::vector<Segmentation> PendingSegmentations::expire(Clock::time_point now) {
  std::vector<Segmentation> expired;
  while (!waiting_.empty() && now - waiting_.front().arrived > timeout_) {
    expired.push_back(std::move(waiting_.front().segmentation));
    waiting_.pop_front();
  }
  return expired;
}

}  // namespace semfuse::server
