#pragma once
// Per-camera bounded queues between the DDS callbacks and the fusion thread. A mapping server that
// falls behind should fuse what the camera sees now, not what it saw a second ago, so the queue
// keeps the newest frames in two ways:
//  - when a camera's queue is full, its oldest frame is dropped;
//  - when a camera falls behind for good, the fusion thread takes its newest frame and the frames
//    before it are dropped. Behind: at its turn, its oldest frame waited longer than `max_wait`;
//    for good: it has not caught up (one frame waiting, not for long) at any turn since it fell
//    behind `backlog_time` ago. A hiccup (a slow frame, a map save) leaves a backlog that drains
//    in a few turns and costs no frame; a camera that sends faster than the fusion thread takes
//    its frames gets its newest fused, a frame period old, instead of one that waited a full
//    queue's worth.
// Cameras are served round-robin so that one fast camera cannot starve the others. Several
// tracking threads take frames with claim(): a camera whose frame is in hand is passed over until
// release(), so that each camera's frames are tracked one at a time, in order.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "semfuse/core/types.hpp"

namespace semfuse::server {

class FrameQueue {
 public:
  using Duration = std::chrono::steady_clock::duration;

  // max_wait zero: frames are taken oldest first however long they waited (replays that must
  // fuse every frame, with a queue as long as the replay).
  explicit FrameQueue(size_t capacity_per_camera, Duration max_wait = Duration::zero(),
                      Duration backlog_time = Duration::zero())
      : capacity_(capacity_per_camera), max_wait_(max_wait), backlog_time_(backlog_time) {}

  // Enqueues; returns the frame evicted to make room, if any (the caller counts it).
  std::optional<Frame> push(Frame frame);

  // Waits up to `timeout` for a frame; the next camera in round-robin order with work. `waited`,
  // when given, receives how long the frame was queued; `stale`, the frames of its camera passed
  // over for it (the caller counts them).
  std::optional<Frame> pop(std::chrono::milliseconds timeout, Duration* waited = nullptr,
                           std::vector<Frame>* stale = nullptr);
  // pop(), of a camera no other caller holds a frame of; the camera is held until release().
  std::optional<Frame> claim(std::chrono::milliseconds timeout, Duration* waited = nullptr,
                             std::vector<Frame>* stale = nullptr);
  void release(const std::string& camera_id);

  // Wakes a waiting pop() (used at shutdown).
  void wake();

  size_t size() const;
  // Cameras whose frame a claim() caller has in hand.
  size_t held() const;

 private:
  struct Queued {
    Frame frame;
    std::chrono::steady_clock::time_point since;
  };
  struct CameraQueue {
    std::deque<Queued> frames;
    // Since when the camera is behind without having caught up; unset while it keeps up.
    std::optional<std::chrono::steady_clock::time_point> behind_since;
  };

  // Drops all but the newest frame of a camera that fell behind for good (see above).
  void passOverStale(CameraQueue& camera, std::chrono::steady_clock::time_point now, std::vector<Frame>* stale);
  std::optional<Frame> take(std::chrono::milliseconds timeout, Duration* waited, std::vector<Frame>* stale,
                            bool hold_camera);
  bool available(const std::string& camera_id, const CameraQueue& camera) const {
    return !camera.frames.empty() && held_.count(camera_id) == 0;
  }
  bool anyAvailable() const;

  size_t capacity_;
  Duration max_wait_;
  Duration backlog_time_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::map<std::string, CameraQueue> queues_;
  std::string last_served_;
  std::set<std::string> held_;  // cameras whose frame a claim() caller has in hand
  size_t total_ = 0;
  bool woken_ = false;
};

}  // namespace semfuse::server
