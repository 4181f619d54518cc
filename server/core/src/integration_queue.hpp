#pragma once
// Tracked frames between the tracking threads and the fusion thread, per camera. Tracking keeps
// up with every frame; integration, the dearer step, takes what the cores allow:
//  - newest first (the default): at a camera's turn the fusion thread takes all of its frames;
//    it integrates the newest posed one, and the older ones are skipped (their depth and pose
//    stay in the frame history, so that their segmentations are still fused);
//  - every frame (replays that must fuse all of them): the oldest frame at each turn, and a
//    tracking thread waits while its camera has `capacity` frames waiting.
// Cameras take turns round robin, so each gets an equal share of the integrations.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "mapper.hpp"

namespace semfuse::server {

class IntegrationQueue {
 public:
  IntegrationQueue(bool every_frame, size_t capacity_per_camera)
      : every_frame_(every_frame), capacity_(capacity_per_camera == 0 ? 1 : capacity_per_camera) {}

  // Tracking threads, a camera's frames in order. With every_frame, waits while the camera has
  // `capacity` frames waiting, until the fusion thread takes one or close() is called.
  void push(PosedFrame frame);

  // Fusion thread: the frames of the next camera that has any, oldest first (only the oldest with
  // every_frame); empty after `timeout` without any, or when woken. They count as in hand until
  // finished().
  std::vector<PosedFrame> take(std::chrono::milliseconds timeout);
  void finished();

  // Wakes a waiting take() (work arrived elsewhere, or shutdown).
  void wake();
  // Stops waiting in push() for good (shutdown): frames are then queued whatever the capacity.
  void close();

  size_t size() const;
  // No frame queued, none in hand.
  bool idle() const;
  bool everyFrame() const { return every_frame_; }

 private:
  const bool every_frame_;
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;  // frames to take, or woken
  std::condition_variable room_;   // a camera's frames taken, or closed
  std::map<std::string, std::deque<PosedFrame>> cameras_;
  std::string last_served_;
  size_t total_ = 0;
  bool in_hand_ = false;
  bool woken_ = false;
  bool closed_ = false;
};

}  // namespace semfuse::server
