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

template <class Matches>
std::vector<Segmentation> PendingSegmentations::takeIf(Matches matches) {
  std::vector<Segmentation> taken;
  for (auto it = waiting_.begin(); it != waiting_.end();) {
    if (matches(it->segmentation)) {
      taken.push_back(std::move(it->segmentation));
      it = waiting_.erase(it);
    } else {
      ++it;
    }
  }
  return taken;
}

std::vector<Segmentation> PendingSegmentations::takeFor(const std::string& camera_id, uint64_t seq) {
  return takeIf([&](const Segmentation& s) { return s.camera_id == camera_id && s.frame_seq == seq; });
}

std::vector<Segmentation> PendingSegmentations::takeBefore(const std::string& camera_id, uint64_t seq) {
  return takeIf([&](const Segmentation& s) { return s.camera_id == camera_id && s.frame_seq < seq; });
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
