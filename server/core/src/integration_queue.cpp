#include "integration_queue.hpp"

#include <utility>

namespace semfuse::server {

void IntegrationQueue::push(PosedFrame frame) {
  {
    std::unique_lock lock(mutex_);
    const std::string camera = frame.frame.camera_id;
    if (every_frame_) room_.wait(lock, [&] { return closed_ || cameras_[camera].size() < capacity_; });
    cameras_[camera].push_back(std::move(frame));
    ++total_;
  }
  ready_.notify_one();
}

std::vector<PosedFrame> IntegrationQueue::take(std::chrono::milliseconds timeout) {
  std::vector<PosedFrame> out;
  {
    std::unique_lock lock(mutex_);
    ready_.wait_for(lock, timeout, [this] { return total_ > 0 || woken_; });
    woken_ = false;
    if (total_ == 0) return out;
    // Round robin: the first camera with frames after the one served last.
    auto it = cameras_.upper_bound(last_served_);
    for (size_t visited = 0; visited <= cameras_.size(); ++visited, ++it) {
      if (it == cameras_.end()) it = cameras_.begin();
      if (!it->second.empty()) break;
    }
    std::deque<PosedFrame>& frames = it->second;
    const size_t count = every_frame_ ? 1 : frames.size();
    for (size_t k = 0; k < count; ++k) {
      out.push_back(std::move(frames.front()));
      frames.pop_front();
    }
    total_ -= count;
    last_served_ = it->first;
    in_hand_ = true;
  }
  room_.notify_all();
  return out;
}

void IntegrationQueue::wake() {
  {
    std::lock_guard lock(mutex_);
    woken_ = true;
  }
  ready_.notify_all();
}

void IntegrationQueue::close() {
  {
    std::lock_guard lock(mutex_);
    closed_ = true;
  }
  room_.notify_all();
}

void IntegrationQueue::finished() {
  std::lock_guard lock(mutex_);
  in_hand_ = false;
}

bool IntegrationQueue::idle() const {
  std::lock_guard lock(mutex_);
  return total_ == 0 && !in_hand_;
}

size_t IntegrationQueue::size() const {
  std::lock_guard lock(mutex_);
  return total_;
}

}  // namespace semfuse::server
