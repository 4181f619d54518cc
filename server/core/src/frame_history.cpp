#include "frame_history.hpp"

#include <algorithm>

namespace semfuse::server {

void FrameHistory::add(HistoryEntry entry) {
  Key key{entry.camera_id, entry.seq};
  auto& last = last_seq_[entry.camera_id];
  last = std::max(last, entry.seq);

  if (auto existing = entries_.find(key); existing != entries_.end()) {
    // A camera that restarted its sequence numbers: the newer frame replaces the old one.
    bytes_ -= existing->second.bytes();
    entries_.erase(existing);
    order_.erase(std::find(order_.begin(), order_.end(), key));
  }
  bytes_ += entry.bytes();
  entries_.emplace(key, std::move(entry));
  order_.push_back(std::move(key));

  while (!order_.empty() && (order_.size() > max_frames_ || bytes_ > max_bytes_)) {
    auto oldest = entries_.find(order_.front());
    bytes_ -= oldest->second.bytes();
    entries_.erase(oldest);
    order_.pop_front();
    ++evicted_;
  }
}

const HistoryEntry* FrameHistory::find(const std::string& camera_id, uint64_t seq) const {
  auto it = entries_.find({camera_id, seq});
  return it == entries_.end() ? nullptr : &it->second;
}

std::optional<uint64_t> FrameHistory::lastSeq(const std::string& camera_id) const {
  auto it = last_seq_.find(camera_id);
  if (it == last_seq_.end()) return std::nullopt;
  return it->second;
}

void FrameHistory::clear() {
  entries_.clear();
  order_.clear();
  last_seq_.clear();
  bytes_ = 0;
}

}  // namespace semfuse::server
