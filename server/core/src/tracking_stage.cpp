#include "tracking_stage.hpp"

#include <sched.h>

#include <algorithm>
#include <string>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"

namespace semfuse::server {
namespace {

// One per core: a thread tracks one camera at a time, and more threads than cores only take
// turns. Past four, one robot's cameras rarely need more and each holds a camera's buffers.
constexpr size_t kMaxDefaultThreads = 4;

// The cores this process may run on (taskset, cgroups' cpusets), not the machine's.
size_t usableCores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

size_t threadCount(size_t asked) { return asked > 0 ? asked : std::min(usableCores(), kMaxDefaultThreads); }

}  // namespace

TrackingStage::TrackingStage(Mapper& mapper, FrameQueue& frames, IntegrationQueue& integration, ServerState& state,
                             size_t threads, PoseCallback on_pose)
    : mapper_(mapper),
      frames_(frames),
      integration_(integration),
      state_(state),
      on_pose_(std::move(on_pose)),
      thread_count_(threadCount(threads)) {}

TrackingStage::~TrackingStage() { stop(); }

void TrackingStage::start() {
  running_ = true;
  for (size_t k = 0; k < thread_count_; ++k)
    threads_.emplace_back([this, k] {
      setCurrentThreadName("sf-track-" + std::to_string(k));
      nameTbbWorkers();
      run();
    });
}

void TrackingStage::stop() {
  if (!running_.exchange(false)) return;
  frames_.wake();
  integration_.close();  // a thread waiting for room at the integration queue finishes its frame
  for (auto& thread : threads_) thread.join();
  threads_.clear();
}

bool TrackingStage::idle() const { return frames_.size() == 0 && frames_.held() == 0; }

void TrackingStage::run() {
  using namespace std::chrono_literals;
  while (running_) {
    FrameQueue::Duration queued{};
    std::vector<Frame> stale;
    auto frame = frames_.claim(20ms, &queued, &stale);
    for (const Frame& dropped : stale) {
      state_.dropped.add(reason::kQueueStale, dropped.camera_id);
      spdlog::debug("camera {}: frame {} waited too long, a newer one is tracked instead", dropped.camera_id,
                    dropped.seq);
    }
    if (!stale.empty()) state_.touch();
    if (!frame) continue;
    const std::string camera = frame->camera_id;
    track(std::move(*frame), queued);
    frames_.release(camera);
  }
}

void TrackingStage::track(Frame frame, std::chrono::steady_clock::duration queued) {
  state_.stages.record(Stage::kFrameQueue, std::chrono::duration<double, std::milli>(queued).count());
  const std::string camera = frame.camera_id;
  const uint64_t seq = frame.seq;
  auto posed = mapper_.track(std::move(frame));
  if (!posed.ok()) {
    state_.reject(reason::kIntegrationFailed, camera, "frame " + camera + "/" + std::to_string(seq), posed.error());
    // The fusion thread still learns of it, so that its segmentations are rejected at once.
    PosedFrame rejected;
    rejected.frame.camera_id = camera;
    rejected.frame.seq = seq;
    rejected.outcome.pose_state = PoseState::kLost;
    rejected.map_epoch = mapper_.epoch();
    rejected.tracked_at = std::chrono::steady_clock::now();
    integration_.push(std::move(rejected));
    return;
  }
  const TrackOutcome& outcome = posed.value().outcome;
  state_.stages.record(Stage::kTrack, outcome.track_ms);
  state_.frameTracked(camera, {outcome.posed(), static_cast<uint8_t>(outcome.pose_state), outcome.lost_reason,
                               outcome.frames_since_lost, outcome.relocalisations});
  if (!outcome.posed()) {
    state_.dropped.add(reason::kTrackingLost, camera);
    spdlog::warn("camera {} frame {}: tracking lost ({}), not integrated", camera, seq, outcome.lost_reason);
  }
  posed.value().tracked_at = std::chrono::steady_clock::now();
  if (on_pose_) on_pose_(posed.value());
  integration_.push(std::move(posed).value());
}

}  // namespace semfuse::server
