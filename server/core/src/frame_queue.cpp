#include "frame_queue.hpp"

#include <utility>

namespace semfuse::server {

std::optional<Frame> FrameQueue::push(Frame frame) {
  std::optional<Frame> evicted;
  {
    std::lock_guard lock(mutex_);
    auto& queue = queues_[frame.camera_id].frames;
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

void FrameQueue::passOverStale(CameraQueue& camera, std::chrono::steady_clock::time_point now,
                               std::vector<Frame>* stale) {
  if (max_wait_ <= Duration::zero()) return;
  const bool late = now - camera.frames.front().since > max_wait_;
  // Caught up: one frame waiting, and not for long. A fresh oldest frame with others behind it
  // is not enough: under a sustained overload a turn that comes early finds one now and then.
  if (!late && camera.frames.size() <= 1) camera.behind_since.reset();
  if (!late) return;
  if (!camera.behind_since) camera.behind_since = now;
  if (now - *camera.behind_since < backlog_time_) return;
  while (camera.frames.size() > 1) {
    if (stale) stale->push_back(std::move(camera.frames.front().frame));
    camera.frames.pop_front();
    --total_;
  }
}

std::optional<Frame> FrameQueue::pop(std::chrono::milliseconds timeout, Duration* waited, std::vector<Frame>* stale) {
  return take(timeout, waited, stale, false);
}

std::optional<Frame> FrameQueue::claim(std::chrono::milliseconds timeout, Duration* waited, std::vector<Frame>* stale) {
  return take(timeout, waited, stale, true);
}

void FrameQueue::release(const std::string& camera_id) {
  {
    std::lock_guard lock(mutex_);
    held_.erase(camera_id);
  }
  ready_.notify_all();
}

bool FrameQueue::anyAvailable() const {
  for (const auto& [id, camera] : queues_)
    if (available(id, camera)) return true;
  return false;
}

std::optional<Frame> FrameQueue::take(std::chrono::milliseconds timeout, Duration* waited, std::vector<Frame>* stale,
                                      bool hold_camera) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [this] { return anyAvailable() || woken_; });
  woken_ = false;
  if (!anyAvailable()) return std::nullopt;

  // Round robin: the first camera with frames, not held, after the camera served last.
  auto it = queues_.upper_bound(last_served_);
  for (size_t visited = 0; visited <= queues_.size(); ++visited) {
    if (it == queues_.end()) it = queues_.begin();
    if (available(it->first, it->second)) break;
    ++it;
  }
  CameraQueue& camera = it->second;
  const auto now = std::chrono::steady_clock::now();
  passOverStale(camera, now, stale);
  Frame frame = std::move(camera.frames.front().frame);
  if (waited) *waited = now - camera.frames.front().since;
  camera.frames.pop_front();
  --total_;
  last_served_ = it->first;
  if (hold_camera) held_.insert(it->first);
  return frame;
}

void FrameQueue::wake() {
  {
    std::lock_guard lock(mutex_);
    woken_ = true;
  }
  ready_.notify_all();
}

size_t FrameQueue::held() const {
  std::lock_guard lock(mutex_);
  return held_.size();
}

size_t FrameQueue::size() const {
  std::lock_guard lock(mutex_);
  return total_;
}

}  // namespace semfuse::server
