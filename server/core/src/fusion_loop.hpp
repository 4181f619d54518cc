#pragma once
// The fusion thread: the only writer of the map. Each turn it runs posted admin tasks (load,
// reset), applies the segmentations that arrived, fuses the next frame (round-robin over
// cameras), then applies segmentations that were waiting for that frame, counts those waiting
// for an earlier frame of that camera (dropped before fusion) and expires the ones that waited
// too long. Every input ends integrated or counted under a reason.
#include <atomic>
#include <chrono>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "frame_history.hpp"
#include "frame_queue.hpp"
#include "fusion_limits.hpp"
#include "mapper.hpp"
#include "pending_segmentations.hpp"
#include "server_state.hpp"

namespace semfuse::server {

class FusionLoop {
 public:
  // Called after each processed frame (integrated or lost) with the outcome, from the fusion
  // thread: the server publishes the pose from here.
  using FrameCallback = std::function<void(const Frame&, const FrameOutcome&)>;

  FusionLoop(Mapper& mapper, FrameQueue& frames, ServerState& state, const FusionLimits& limits,
             FrameCallback on_frame);
  ~FusionLoop();

  void start();
  // Stops taking tasks (runOnFusionThread answers UNAVAILABLE at once from now on); the tasks
  // already posted still run. The first step of stop(), and of the server's stop sequence.
  void closeTasks();
  // closeTasks, then the thread runs what was posted and ends. A task it never ran (the loop was
  // not started) is answered UNAVAILABLE: nobody waits out a timeout for a thread that is gone.
  void stop();

  // From any thread: a decoded, validated segmentation to apply.
  void submitSegmentation(Segmentation segmentation);

  // Runs `task` on the fusion thread between two frames and returns its result; UNAVAILABLE when
  // the thread did not run it within `timeout`, and at once when the loop no longer takes tasks.
  Status runOnFusionThread(std::function<Status()> task, std::chrono::milliseconds timeout);

  size_t pendingSegmentations() const;
  size_t historyFrames() const;
  bool idle() const;  // no queued frame, no queued segmentation or task, nothing in progress
  // Waits until idle(), at most `timeout`; returns at once when the thread does not run.
  void drain(std::chrono::milliseconds timeout) const;

 private:
  void run();
  void runTasks();
  void processFrame(Frame frame);
  void applySegmentation(Segmentation segmentation);
  void integrateLabels(const HistoryEntry& entry, const Segmentation& segmentation);
  void expirePending();

  Mapper& mapper_;
  FrameQueue& frames_;
  ServerState& state_;
  FrameCallback on_frame_;

  FrameHistory history_;          // fusion thread only
  PendingSegmentations pending_;  // fusion thread only
  std::atomic<size_t> history_size_{0};
  std::atomic<size_t> pending_size_{0};
  std::atomic<bool> busy_{false};

  struct Task {
    std::function<Status()> run;
    std::promise<Status> done;
  };

  mutable std::mutex inbox_mutex_;
  std::vector<Segmentation> inbox_;
  std::vector<Task> tasks_;
  bool taking_tasks_ = true;  // under inbox_mutex_; false from closeTasks() on

  std::atomic<bool> running_{false};
  std::thread thread_;
};

}  // namespace semfuse::server
