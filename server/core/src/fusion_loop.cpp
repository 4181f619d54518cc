#include "fusion_loop.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"

namespace semfuse::server {

FusionLoop::FusionLoop(Mapper& mapper, FrameQueue& frames, ServerState& state, const FusionLimits& limits,
                       FrameCallback on_frame)
    : mapper_(mapper),
      frames_(frames),
      state_(state),
      on_frame_(std::move(on_frame)),
      history_(limits.history_frames, limits.history_megabytes << 20),
      pending_(limits.pending_segmentations,
               std::chrono::milliseconds(static_cast<int64_t>(limits.pending_timeout_s * 1000))) {}

FusionLoop::~FusionLoop() { stop(); }

void FusionLoop::start() {
  running_ = true;
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-fusion");
    nameTbbWorkers();
    run();
  });
}

void FusionLoop::closeTasks() {
  std::lock_guard lock(inbox_mutex_);
  taking_tasks_ = false;
}

void FusionLoop::stop() {
  closeTasks();
  if (running_.exchange(false)) {
    frames_.wake();
    if (thread_.joinable()) thread_.join();  // its last turn runs the tasks posted before closeTasks
  }
  std::vector<Task> never_run;
  {
    std::lock_guard lock(inbox_mutex_);
    never_run.swap(tasks_);
  }
  for (auto& task : never_run)
    task.done.set_value(
        makeError(ErrorCode::kUnavailable, "the server is shutting down (the fusion thread is not running)"));
}

void FusionLoop::submitSegmentation(Segmentation segmentation) {
  {
    std::lock_guard lock(inbox_mutex_);
    inbox_.push_back(std::move(segmentation));
  }
  frames_.wake();  // the fusion thread may be waiting for a frame
}

Status FusionLoop::runOnFusionThread(std::function<Status()> task, std::chrono::milliseconds timeout) {
  std::future<Status> result;
  {
    std::lock_guard lock(inbox_mutex_);
    if (!taking_tasks_) return makeError(ErrorCode::kUnavailable, "the server is shutting down");
    tasks_.push_back({std::move(task), {}});
    result = tasks_.back().done.get_future();
  }
  frames_.wake();
  if (result.wait_for(timeout) != std::future_status::ready)
    return makeError(ErrorCode::kUnavailable, "the fusion thread did not run the request within " +
                                                  std::to_string(timeout.count()) + " ms (busy integrating)");
  return result.get();
}

size_t FusionLoop::pendingSegmentations() const { return pending_size_.load(); }
size_t FusionLoop::historyFrames() const { return history_size_.load(); }

bool FusionLoop::idle() const {
  std::lock_guard lock(inbox_mutex_);
  return inbox_.empty() && tasks_.empty() && frames_.size() == 0 && !busy_.load();
}

void FusionLoop::drain(std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (running_ && !idle() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

void FusionLoop::run() {
  using namespace std::chrono_literals;
  while (running_) {
    runTasks();
    std::vector<Segmentation> arrived;
    {
      std::lock_guard lock(inbox_mutex_);
      arrived.swap(inbox_);
      busy_ = !arrived.empty();
    }
    for (auto& segmentation : arrived) applySegmentation(std::move(segmentation));

    std::chrono::steady_clock::duration queued{};
    std::vector<Frame> stale;
    auto frame = frames_.pop(20ms, &queued, &stale);
    for (const Frame& dropped : stale) {
      state_.dropped.add(reason::kQueueStale, dropped.camera_id);
      spdlog::debug("camera {}: frame {} waited too long, a newer one is fused instead", dropped.camera_id,
                    dropped.seq);
    }
    if (!stale.empty()) state_.touch();
    if (frame) {
      busy_ = true;
      state_.stages.record(Stage::kFrameQueue, std::chrono::duration<double, std::milli>(queued).count());
      processFrame(std::move(*frame));
    }
    expirePending();
    pending_size_ = pending_.size();
    history_size_ = history_.size();
    busy_ = false;
  }
  runTasks();  // the tasks posted before closeTasks(); later ones were refused
}

void FusionLoop::runTasks() {
  std::vector<Task> tasks;
  {
    std::lock_guard lock(inbox_mutex_);
    tasks.swap(tasks_);
    if (!tasks.empty()) busy_ = true;  // idle() is false while they run
  }
  for (auto& task : tasks) {
    try {
      task.done.set_value(task.run());
    } catch (...) {
      task.done.set_exception(std::current_exception());  // rethrown to the caller, as it would be there
    }
    // A load or reset invalidates every frame the history holds and every waiting segmentation.
    history_.clear();
    for (auto& waiting : pending_.expire(PendingSegmentations::Clock::time_point::max()))
      state_.dropped.add(reason::kUnknownFrame, waiting.camera_id);
  }
}

void FusionLoop::processFrame(Frame frame) {
  // The camera's earlier frames are fused or gone: segmentations still waiting for one of them
  // are counted now, so that the waiting set holds only those that can still be fused.
  for (const auto& orphaned : pending_.takeBefore(frame.camera_id, frame.seq)) {
    state_.dropped.add(reason::kFrameDropped, orphaned.camera_id);
    spdlog::debug("segmentation {} of {}/{}: its frame was dropped before fusion", orphaned.segmenter_id,
                  orphaned.camera_id, orphaned.frame_seq);
  }
  // A segmentation that was already waiting is fused in the same pass as the depth (one walk
  // over the voxels instead of two); any further ones for this frame follow separately.
  std::vector<Segmentation> waiting = pending_.takeFor(frame.camera_id, frame.seq);
  const Segmentation* same_pass = nullptr;
  for (const auto& candidate : waiting) {
    if (candidate.labels.cols <= frame.depth.cols && candidate.labels.rows <= frame.depth.rows) {
      same_pass = &candidate;
      break;
    }
  }
  auto outcome = mapper_.integrateFrame(frame, same_pass);
  if (!outcome.ok()) {
    state_.reject(reason::kIntegrationFailed, frame.camera_id,
                  "frame " + frame.camera_id + "/" + std::to_string(frame.seq), outcome.error());
    // Remember the frame so its segmentations are rejected at once instead of waiting.
    history_.add({frame.camera_id, frame.seq, false, frame.intrinsics, cv::Mat(), Pose::Identity()});
    for (const auto& segmentation : waiting) state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
    return;
  }
  const FrameOutcome& result = outcome.value();
  state_.stages.record(Stage::kTrack, result.track_ms);
  if (result.integrated) state_.stages.record(Stage::kIntegrate, result.integrate_ms);
  const auto tracking_state = static_cast<uint8_t>(result.pose_state);
  if (result.integrated) {
    ++state_.frames_integrated;
  } else {
    ++state_.frames_lost;
    state_.dropped.add(reason::kTrackingLost, frame.camera_id);
    spdlog::warn("camera {} frame {}: tracking lost ({}), not integrated", frame.camera_id, frame.seq,
                 result.lost_reason);
  }
  state_.frameProcessed(frame.camera_id, {result.integrated, tracking_state, result.lost_reason,
                                          result.frames_since_lost, result.relocalisations});
  if (on_frame_) on_frame_(frame, result);

  HistoryEntry entry{frame.camera_id,
                     frame.seq,
                     result.integrated,
                     frame.intrinsics,
                     result.integrated ? frame.depth : cv::Mat(),
                     result.camera_to_world};
  history_.add(std::move(entry));
  const HistoryEntry* stored = history_.find(frame.camera_id, frame.seq);
  for (const auto& segmentation : waiting) {
    if (&segmentation == same_pass && result.integrated) {
      ++state_.segmentations_integrated;
    } else if (stored && stored->integrated) {
      integrateLabels(*stored, segmentation);
    } else {
      state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
    }
  }
}

void FusionLoop::applySegmentation(Segmentation segmentation) {
  const std::string& camera = segmentation.camera_id;
  if (const HistoryEntry* entry = history_.find(camera, segmentation.frame_seq)) {
    if (!entry->integrated) {
      state_.reject(reason::kUnknownFrame, camera, "segmentation " + segmentation.segmenter_id,
                    "frame " + camera + "/" + std::to_string(segmentation.frame_seq) +
                        " was not integrated (tracking lost or rejected): its labels have no geometry");
      return;
    }
    integrateLabels(*entry, segmentation);
    return;
  }
  // Not in the history: either the frame is still on its way (wait for it), or it is gone.
  const auto last = history_.lastSeq(camera);
  if (last && segmentation.frame_seq <= *last) {
    state_.reject(reason::kUnknownFrame, camera, "segmentation " + segmentation.segmenter_id,
                  "frame " + camera + "/" + std::to_string(segmentation.frame_seq) +
                      " is no longer in the frame history (evicted or never received)");
    return;
  }
  for (auto& evicted : pending_.add(std::move(segmentation))) {
    state_.dropped.add(reason::kPendingFull, evicted.camera_id);
    state_.touch();
  }
}

void FusionLoop::integrateLabels(const HistoryEntry& entry, const Segmentation& segmentation) {
  if (segmentation.labels.cols > entry.depth.cols || segmentation.labels.rows > entry.depth.rows) {
    state_.reject(reason::kSizeMismatch, segmentation.camera_id, "segmentation " + segmentation.segmenter_id,
                  "labels " + std::to_string(segmentation.labels.cols) + "x" +
                      std::to_string(segmentation.labels.rows) + " are larger than frame " + std::to_string(entry.seq) +
                      "'s depth " + std::to_string(entry.depth.cols) + "x" + std::to_string(entry.depth.rows));
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  auto stats = mapper_.integrateSegmentation(entry, segmentation);
  state_.stages.recordSince(Stage::kLateLabels, start);
  if (!stats.ok()) {
    state_.reject(reason::kInvalidSegmentation, segmentation.camera_id, "segmentation " + segmentation.segmenter_id,
                  stats.error());
    return;
  }
  ++state_.segmentations_integrated;
  state_.touch();
}

void FusionLoop::expirePending() {
  for (auto& expired : pending_.expire()) {
    const bool camera_known = state_.knowsCamera(expired.camera_id);
    if (camera_known) {
      state_.dropped.add(reason::kSegmentationTimeout, expired.camera_id);
      state_.errors.record("segmentation " + expired.segmenter_id, "frame " + expired.camera_id + "/" +
                                                                       std::to_string(expired.frame_seq) +
                                                                       " never arrived; segmentation dropped");
      state_.touch();
    } else {
      state_.reject(reason::kUnknownCamera, expired.camera_id, "segmentation " + expired.segmenter_id,
                    "no frame from camera '" + expired.camera_id + "' ever arrived");
    }
  }
}

}  // namespace semfuse::server
