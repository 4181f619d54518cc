#include "frame_queue.hpp"

#include <utility>

namespace semfuse::server {

std::optional<Frame> FrameQueue::push(Frame frame) {
  std::optional<Frame> evicted;
  {
    std::lock_guard lock(mutex_);
    auto& queue = queues_[frame.camera_id];
    if (capacity_ > 0 && queue.size() >= capacity_) {
      evicted = std::move(queue.front().frame);
      queue.pop_front();
      --total_;
    }
    queue.push_back({std::move(frame), std::chrono::steady_clock::now()});
    ++total_;
  }
  ready_.notify_one();
  return evicted;
}

std::optional<Frame> FrameQueue::pop(std::chrono::milliseconds timeout, std::chrono::steady_clock::duration* waited) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [this] { return total_ > 0 || woken_; });
  woken_ = false;
  if (total_ == 0) return std::nullopt;

  // Round robin: the first non-empty queue after the camera served last.
  auto it = queues_.upper_bound(last_served_);
  for (size_t visited = 0; visited <= queues_.size(); ++visited) {
    if (it == queues_.end()) it = queues_.begin();
    if (!it->second.empty()) break;
    ++it;
  }
  Frame frame = std::move(it->second.front().frame);
  if (waited) *waited = std::chrono::steady_clock::now() - it->second.front().since;
  it->second.pop_front();
  --total_;
  last_served_ = it->first;
  return frame;
}

void FrameQueue::wake() {
  {
    std::lock_guard lock(mutex_);
    woken_ = true;
  }
  ready_.notify_all();
}

size_t FrameQueue::size() const {
  std::lock_guard lock(mutex_);
  return total_;
}

}  // namespace semfuse::server
