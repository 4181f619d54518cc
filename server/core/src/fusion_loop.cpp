#include "fusion_loop.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {
namespace {

// Frames a camera may have tracked ahead of integration when every frame is integrated: enough
// to keep the fusion thread fed while the tracker works on the next.
constexpr size_t kEveryFrameAhead = 2;

// Label passes that may wait for the fusion thread when frames come newest first: about a second
// of them on a busy 2-core machine. Beyond it the oldest is dropped, so that a segmenter faster
// than the map cannot take the integration's share of the thread.
constexpr size_t kQueuedLabelPasses = 16;

std::string frameName(const std::string& camera, uint64_t seq) { return camera + "/" + std::to_string(seq); }

}  // namespace

FusionLoop::FusionLoop(Mapper& mapper, FrameQueue& frames, ServerState& state, const FusionLimits& limits,
                       PoseCallback on_pose)
    : mapper_(mapper),
      state_(state),
      integration_(limits.integrate_every_frame, kEveryFrameAhead),
      tracking_(mapper, frames, integration_, state, limits.tracking_threads, std::move(on_pose)),
      history_(limits.history_frames, limits.history_megabytes << 20),
      pending_(limits.pending_segmentations,
               std::chrono::milliseconds(static_cast<int64_t>(limits.pending_timeout_s * 1000))) {}

FusionLoop::~FusionLoop() { stop(); }

void FusionLoop::start() {
  running_ = true;
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-fusion");
    lowerToMapPriority();  // poses first (thread_priority.hpp)
    nameTbbWorkers();
    run();
  });
  tracking_.start();
}

void FusionLoop::closeTasks() {
  std::lock_guard lock(inbox_mutex_);
  taking_tasks_ = false;
}

void FusionLoop::stop() {
  closeTasks();
  tracking_.stop();
  if (running_.exchange(false)) {
    integration_.wake();
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
  integration_.wake();  // the fusion thread may be waiting for a frame
}

Status FusionLoop::runOnFusionThread(std::function<Status()> task, std::chrono::milliseconds timeout) {
  std::future<Status> result;
  {
    std::lock_guard lock(inbox_mutex_);
    if (!taking_tasks_) return makeError(ErrorCode::kUnavailable, "the server is shutting down");
    tasks_.push_back({std::move(task), {}});
    result = tasks_.back().done.get_future();
  }
  integration_.wake();
  if (result.wait_for(timeout) != std::future_status::ready)
    return makeError(ErrorCode::kUnavailable, "the fusion thread did not run the request within " +
                                                  std::to_string(timeout.count()) + " ms (busy integrating)");
  return result.get();
}

size_t FusionLoop::pendingSegmentations() const { return pending_size_.load(); }
size_t FusionLoop::historyFrames() const { return history_size_.load(); }

bool FusionLoop::idle() const {
  {
    std::lock_guard lock(inbox_mutex_);
    if (!inbox_.empty() || !tasks_.empty()) return false;
  }
  return tracking_.idle() && integration_.idle() && label_passes_size_.load() == 0 && !busy_.load();
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

    // Label passes to run: look for frames without waiting for them.
    std::vector<PosedFrame> frames = integration_.take(label_passes_.empty() ? 20ms : 0ms);
    std::chrono::steady_clock::duration integrating{0};
    if (!frames.empty()) {
      busy_ = true;
      const auto start = std::chrono::steady_clock::now();
      processFrames(std::move(frames));
      integrating = std::chrono::steady_clock::now() - start;
    }
    runLabelPasses(integrating);
    expirePending();
    pending_size_ = pending_.size() + label_passes_.size();
    label_passes_size_ = label_passes_.size();
    history_size_ = history_.size();
    busy_ = false;
    integration_.finished();
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
    for (const auto& queued : label_passes_) state_.dropped.add(reason::kUnknownFrame, queued.camera_id);
    label_passes_.clear();
  }
}

void FusionLoop::processFrames(std::vector<PosedFrame> frames) {
  const uint64_t epoch = mapper_.epoch();
  // The newest posed frame of today's map is integrated; with every frame integrated there is one.
  std::ptrdiff_t chosen = -1;
  for (auto k = static_cast<std::ptrdiff_t>(frames.size()) - 1; k >= 0 && chosen < 0; --k)
    if (frames[k].outcome.posed() && frames[k].map_epoch == epoch) chosen = k;

  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(frames.size()); ++k) {
    const PosedFrame& posed = frames[static_cast<size_t>(k)];
    const std::string& camera = posed.frame.camera_id;
    const uint64_t seq = posed.frame.seq;
    state_.stages.recordSince(Stage::kIntegrationQueue, posed.tracked_at);
    // The camera's earlier frames are fused, kept or gone: segmentations still waiting for one of
    // them are counted now, so that the waiting set holds only those that can still be fused.
    for (const auto& orphaned : pending_.takeBefore(camera, seq)) {
      state_.dropped.add(reason::kFrameDropped, orphaned.camera_id);
      spdlog::debug("segmentation {} of {}: its frame was dropped before tracking", orphaned.segmenter_id,
                    frameName(camera, orphaned.frame_seq));
    }
    std::vector<Segmentation> waiting = pending_.takeFor(camera, seq);
    if (k == chosen) {
      integrateFrame(posed, std::move(waiting));
    } else if (posed.outcome.posed() && posed.map_epoch != epoch) {
      // Tracked against a map a load or reset replaced: its pose means nothing in this one.
      mapper_.abandon(posed);
      state_.dropped.add(reason::kMapReplaced, camera);
      for (const auto& segmentation : waiting) state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
      state_.touch();
    } else {
      if (posed.outcome.posed()) {
        mapper_.abandon(posed);
        state_.frameSkipped(camera);
      }
      keepFrame(posed, std::move(waiting));
    }
  }
}

void FusionLoop::integrateFrame(const PosedFrame& posed, std::vector<Segmentation> waiting) {
  const Frame& frame = posed.frame;
  // A segmentation that was already waiting is fused in the same pass as the depth (one walk
  // over the voxels instead of two); any further ones for this frame follow separately.
  const Segmentation* same_pass = nullptr;
  for (const auto& candidate : waiting) {
    if (candidate.labels.cols <= frame.depth.cols && candidate.labels.rows <= frame.depth.rows) {
      same_pass = &candidate;
      break;
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto stats = mapper_.integrate(posed, same_pass);
  state_.stages.recordSince(Stage::kIntegrate, start);
  if (!stats.ok()) {
    state_.reject(reason::kIntegrationFailed, frame.camera_id, "frame " + frameName(frame.camera_id, frame.seq),
                  stats.error());
    // Remember the frame so its segmentations are rejected at once instead of waiting.
    history_.add({frame.camera_id, frame.seq, false, frame.intrinsics, cv::Mat(), Pose::Identity()});
    for (const auto& segmentation : waiting) state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
    return;
  }
  state_.frameIntegrated(frame.camera_id);
  history_.add({frame.camera_id, frame.seq, true, frame.intrinsics, frame.depth, *frame.camera_to_world});
  const HistoryEntry* stored = history_.find(frame.camera_id, frame.seq);
  for (auto& segmentation : waiting) {
    if (&segmentation == same_pass) {
      ++state_.segmentations_integrated;
      state_.touch();
    } else if (stored) {
      queueLabelPass(std::move(segmentation));
    } else {
      state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
    }
  }
}

void FusionLoop::keepFrame(const PosedFrame& posed, std::vector<Segmentation> waiting) {
  const Frame& frame = posed.frame;
  const bool has_pose = posed.outcome.posed();
  history_.add({frame.camera_id, frame.seq, has_pose, frame.intrinsics, has_pose ? frame.depth : cv::Mat(),
                has_pose ? *frame.camera_to_world : Pose::Identity()});
  const HistoryEntry* stored = history_.find(frame.camera_id, frame.seq);
  for (auto& segmentation : waiting) {
    if (stored && stored->posed) queueLabelPass(std::move(segmentation));
    else state_.dropped.add(reason::kUnknownFrame, segmentation.camera_id);
  }
}

void FusionLoop::applySegmentation(Segmentation segmentation) {
  const std::string& camera = segmentation.camera_id;
  if (const HistoryEntry* entry = history_.find(camera, segmentation.frame_seq)) {
    if (!entry->posed) {
      state_.reject(reason::kUnknownFrame, camera, "segmentation " + segmentation.segmenter_id,
                    "frame " + frameName(camera, segmentation.frame_seq) +
                        " has no pose (tracking lost or frame rejected): its labels have no geometry");
      return;
    }
    queueLabelPass(std::move(segmentation));
    return;
  }
  // Not in the history: either the frame is still on its way (wait for it), or it is gone.
  const auto last = history_.lastSeq(camera);
  if (last && segmentation.frame_seq <= *last) {
    state_.reject(reason::kUnknownFrame, camera, "segmentation " + segmentation.segmenter_id,
                  "frame " + frameName(camera, segmentation.frame_seq) +
                      " is no longer in the frame history (evicted or never received)");
    return;
  }
  for (auto& evicted : pending_.add(std::move(segmentation))) {
    state_.dropped.add(reason::kPendingFull, evicted.camera_id);
    state_.touch();
  }
}

void FusionLoop::queueLabelPass(Segmentation segmentation) {
  label_passes_.push_back(std::move(segmentation));
  if (integration_.everyFrame() || label_passes_.size() <= kQueuedLabelPasses) return;
  state_.dropped.add(reason::kLabelsBehind, label_passes_.front().camera_id);
  state_.touch();
  label_passes_.pop_front();
}

void FusionLoop::runLabelPasses(std::chrono::steady_clock::duration integrating) {
  label_budget_.earn(integrating);
  while (!label_passes_.empty()) {
    const bool frames_wait = !integration_.everyFrame() && integration_.size() > 0;
    if (!label_budget_.allows(frames_wait)) break;
    const auto start = std::chrono::steady_clock::now();
    const Segmentation segmentation = std::move(label_passes_.front());
    label_passes_.pop_front();
    if (const HistoryEntry* entry = history_.find(segmentation.camera_id, segmentation.frame_seq))
      integrateLabels(*entry, segmentation);
    else
      state_.reject(reason::kUnknownFrame, segmentation.camera_id, "segmentation " + segmentation.segmenter_id,
                    "frame " + frameName(segmentation.camera_id, segmentation.frame_seq) +
                        " left the frame history before its label pass");
    label_budget_.spend(frames_wait, std::chrono::steady_clock::now() - start);
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
      state_.errors.record(
          "segmentation " + expired.segmenter_id,
          "frame " + frameName(expired.camera_id, expired.frame_seq) + " never arrived; segmentation dropped");
      state_.touch();
    } else {
      state_.reject(reason::kUnknownCamera, expired.camera_id, "segmentation " + expired.segmenter_id,
                    "no frame from camera '" + expired.camera_id + "' ever arrived");
    }
  }
}

}  // namespace semfuse::server
