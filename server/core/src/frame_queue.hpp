#pragma once
// Per-camera bounded queues between the DDS callbacks and the fusion thread. When a camera's
// queue is full the oldest frame is dropped ("keep the newest"): a mapping server that falls
// behind should fuse what the camera sees now, not what it saw a second ago. Cameras are served
// round-robin so that one fast camera cannot starve the others.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "semfuse/core/types.hpp"

namespace semfuse::server {

class FrameQueue {
 public:
  explicit FrameQueue(size_t capacity_per_camera) : capacity_(capacity_per_camera) {}

  // Enqueues; returns the frame evicted to make room, if any (the caller counts it).
  std::optional<Frame> push(Frame frame);

  // Waits up to `timeout` for a frame; the next camera in round-robin order with work. `waited`,
  // when given, receives how long the frame was queued.
  std::optional<Frame> pop(std::chrono::milliseconds timeout, std::chrono::steady_clock::duration* waited = nullptr);

  // Wakes a waiting pop() (used at shutdown).
  void wake();

  size_t size() const;

 private:
  size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  struct Queued {
    Frame frame;
    std::chrono::steady_clock::time_point since;
  };
  std::map<std::string, std::deque<Queued>> queues_;
  std::string last_served_;
  size_t total_ = 0;
  bool woken_ = false;
};

}  // namespace semfuse::server
