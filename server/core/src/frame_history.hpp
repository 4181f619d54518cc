#pragma once
// The recent frames the map was built from: depth, pose and intrinsics per (camera, seq). A
// segmentation usually arrives after its frame (segmenters are slower than cameras), possibly
// after later frames were fused; it is integrated with its own frame's depth and pose, looked up
// here. Bounded by count and by memory; the oldest frames go first.
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "semfuse/core/types.hpp"

namespace semfuse::server {

struct HistoryEntry {
  std::string camera_id;
  uint64_t seq = 0;
  // Has depth and a pose its labels can be fused at (integrated, or skipped for a newer frame of
  // its camera); false: tracking lost or the frame rejected, it has no geometry.
  bool posed = false;
  PinholeIntrinsics intrinsics;
  cv::Mat depth;  // CV_32FC1 metres; empty when not posed
  Pose camera_to_world = Pose::Identity();

  size_t bytes() const { return depth.total() * depth.elemSize() + sizeof(*this); }
};

class FrameHistory {
 public:
  FrameHistory(size_t max_frames, size_t max_bytes) : max_frames_(max_frames), max_bytes_(max_bytes) {}

  void add(HistoryEntry entry);
  const HistoryEntry* find(const std::string& camera_id, uint64_t seq) const;

  // Highest seq processed for a camera (integrated or lost), if the camera was ever seen.
  std::optional<uint64_t> lastSeq(const std::string& camera_id) const;

  size_t size() const { return order_.size(); }
  size_t bytes() const { return bytes_; }
  uint64_t evicted() const { return evicted_; }
  void clear();

 private:
  using Key = std::pair<std::string, uint64_t>;
  size_t max_frames_;
  size_t max_bytes_;
  size_t bytes_ = 0;
  uint64_t evicted_ = 0;
  std::map<Key, HistoryEntry> entries_;
  std::deque<Key> order_;  // insertion order, oldest first
  std::map<std::string, uint64_t> last_seq_;
};

}  // namespace semfuse::server
