#pragma once
// The frame pipeline behind the ingest: tracking threads give every frame its pose
// (TrackingStage), and the fusion thread, the only writer of the map, integrates them from the
// integration queue. Each turn the fusion thread runs posted admin tasks (load, reset), applies
// the segmentations that arrived, then takes the tracked frames of the next camera (round robin):
// the newest posed one is integrated, the older ones are skipped and kept in the frame history
// (their segmentations still get a label pass), lost ones are kept there as such. It applies the
// segmentations that were waiting for those frames, counts those waiting for an earlier frame of
// that camera (dropped before tracking) and expires the ones that waited too long. Label passes
// queue and get as much of the thread as the turn's integration while frames wait, so that a
// fast segmenter cannot starve the map. Every input ends integrated or counted under a reason.
#include <atomic>
#include <chrono>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "frame_history.hpp"
#include "frame_queue.hpp"
#include "fusion_limits.hpp"
#include "integration_queue.hpp"
#include "label_pass_budget.hpp"
#include "mapper.hpp"
#include "pending_segmentations.hpp"
#include "server_state.hpp"
#include "tracking_stage.hpp"

namespace semfuse::server {

class FusionLoop {
 public:
  using PoseCallback = TrackingStage::PoseCallback;

  // on_pose: called on a tracking thread for every tracked frame, posed or lost, as soon as its
  // pose is known (the server publishes it from here).
  FusionLoop(Mapper& mapper, FrameQueue& frames, ServerState& state, const FusionLimits& limits, PoseCallback on_pose);
  ~FusionLoop();

  void start();
  // Stops taking tasks (runOnFusionThread answers UNAVAILABLE at once from now on); the tasks
  // already posted still run. The first step of stop(), and of the server's stop sequence.
  void closeTasks();
  // closeTasks, then the threads finish what they hold and end. A task the fusion thread never
  // ran (the loop was not started) is answered UNAVAILABLE: nobody waits out a timeout for a
  // thread that is gone.
  void stop();

  // From any thread: a decoded, validated segmentation to apply.
  void submitSegmentation(Segmentation segmentation);

  // Runs `task` on the fusion thread between two frames and returns its result; UNAVAILABLE when
  // the thread did not run it within `timeout`, and at once when the loop no longer takes tasks.
  Status runOnFusionThread(std::function<Status()> task, std::chrono::milliseconds timeout);

  // Segmentations waiting for their frame or for their label pass (the status's pending_segmentations).
  size_t pendingSegmentations() const;
  size_t historyFrames() const;
  size_t trackingThreads() const { return tracking_.threads(); }
  // Frames tracked and waiting for the fusion thread.
  size_t framesAwaitingIntegration() const { return integration_.size(); }
  // No frame queued or in hand anywhere, no queued segmentation or task, nothing in progress.
  bool idle() const;
  // Waits until idle(), at most `timeout`; returns at once when the threads do not run.
  void drain(std::chrono::milliseconds timeout) const;

 private:
  void run();
  void runTasks();
  // The tracked frames of one camera, oldest first.
  void processFrames(std::vector<PosedFrame> frames);
  void integrateFrame(const PosedFrame& frame, std::vector<Segmentation> waiting);
  // A frame kept in the history without being integrated: posed and skipped, or without a pose.
  void keepFrame(const PosedFrame& frame, std::vector<Segmentation> waiting);
  void applySegmentation(Segmentation segmentation);
  // A segmentation of a posed frame in the history, fused by a label pass of its own.
  void queueLabelPass(Segmentation segmentation);
  void runLabelPasses(std::chrono::steady_clock::duration integrating);
  void integrateLabels(const HistoryEntry& entry, const Segmentation& segmentation);
  void expirePending();

  Mapper& mapper_;
  ServerState& state_;
  IntegrationQueue integration_;
  TrackingStage tracking_;

  FrameHistory history_;                   // fusion thread only
  PendingSegmentations pending_;           // fusion thread only
  std::deque<Segmentation> label_passes_;  // fusion thread only, oldest first
  LabelPassBudget label_budget_;           // fusion thread only
  std::atomic<size_t> label_passes_size_{0};
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
