#pragma once
// The tracking threads: every frame of every camera gets its pose here, in order, as soon as a
// thread is free, whatever the integration is doing. Tracking only reads the map, so cameras are
// tracked at the same time on as many threads as there are cores for them; a camera's frames go
// one at a time (FrameQueue::claim). Each tracked frame is handed to the callback (the server
// publishes its pose) and then to the integration queue, posed or lost.
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

#include "frame_queue.hpp"
#include "integration_queue.hpp"
#include "mapper.hpp"
#include "server_state.hpp"

namespace semfuse::server {

class TrackingStage {
 public:
  // Called on a tracking thread for every frame tracked, posed or lost, before it goes on.
  using PoseCallback = std::function<void(const PosedFrame&)>;

  // threads: 0 = one per core, at most 4.
  TrackingStage(Mapper& mapper, FrameQueue& frames, IntegrationQueue& integration, ServerState& state, size_t threads,
                PoseCallback on_pose);
  ~TrackingStage();

  void start();
  // The frames in hand are finished; queued ones stay queued.
  void stop();

  size_t threads() const { return thread_count_; }
  // No frame queued for tracking, none in hand.
  bool idle() const;

 private:
  void run();
  void track(Frame frame, std::chrono::steady_clock::duration queued);

  Mapper& mapper_;
  FrameQueue& frames_;
  IntegrationQueue& integration_;
  ServerState& state_;
  PoseCallback on_pose_;
  size_t thread_count_;

  std::atomic<bool> running_{false};
  std::atomic<size_t> in_hand_{0};
  std::vector<std::thread> threads_;
};

}  // namespace semfuse::server
