#pragma once
// Mapper: the one object that owns the map (nvblox-style facade). A frame goes through it in two
// steps: track() picks its pose (given, refined or tracked) under the map's shared lock, on a
// tracking thread, several cameras at once; integrate() fuses its depth, colour and labels, on the
// fusion thread, the map's only writer. integrateSegmentation() adds a late segmentation's label
// evidence. Queries read under the shared lock, so they run concurrently with each other and with
// tracking, and wait only for the write in progress. Saving copies the volume under the shared
// lock and writes the copy without holding it.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>
#include <string>

#include "frame_history.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/tracking/tracker.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/labeled_volume.hpp"
#include "semfuse/volume/map_file.hpp"
#include "writer_first_mutex.hpp"

namespace semfuse::server {

// What tracking made of a frame: the pose it goes to the map at, or why it has none.
struct TrackOutcome {
  PoseState pose_state = PoseState::kGiven;
  Pose camera_to_world = Pose::Identity();
  float inlier_ratio = 1.0f;
  float residual = 0.0f;
  uint32_t iterations = 0;
  double track_ms = 0.0;
  std::string lost_reason;  // why tracking gave up (pose_state == kLost)
  // The camera's tracking after this frame: frames the current loss has lasted (0 while
  // tracking) and times a keyframe found it again or placed it.
  uint64_t frames_since_lost = 0;
  uint64_t relocalisations = 0;
  bool posed() const { return pose_state != PoseState::kLost; }
};

// A tracked frame on its way to the map.
struct PosedFrame {
  Frame frame;  // camera_to_world: the pose tracking chose (unset when lost)
  TrackOutcome outcome;
  tracking::TrackedFrame tracked;                      // for the keyframes, once the frame is integrated
  uint64_t map_epoch = 0;                              // the map it was tracked against (Mapper::epoch)
  std::chrono::steady_clock::time_point tracked_at{};  // when its pose was known
};

// Tracking and integration of one frame in one call (integrateFrame).
struct FrameOutcome : TrackOutcome {
  bool integrated = false;
  double integrate_ms = 0.0;
  volume::IntegrationStats stats;
};

struct MapperOptions {
  volume::VolumeParams volume;
  LabelLegend legend;
  bool refine_given_poses = false;
  tracking::TrackerParams tracker;
  // Also mark the free space each integrated frame saw (volume/free_space.hpp), for the distance
  // field: it costs a pass over the frame's view under the map's lock.
  bool observe_free_space = false;
  // Within partly seen leaves, only every n-th voxel along each axis: the distance field's stride
  // (esdf::EsdfParams::stride), which reads no other.
  int free_space_stride = 1;
};

class Mapper {
 public:
  explicit Mapper(MapperOptions options);

  // Any thread, one frame of a camera at a time and in order. Errors: bad input (sizes,
  // intrinsics, a pose that is not rigid). A frame the tracker cannot place (lost, or a pose-less
  // camera no keyframe has placed yet) is no error: its outcome says why it has no pose.
  Result<PosedFrame> track(Frame frame);
  // Fusion thread only: fuses a posed frame (and the labels and instances of a segmentation of it)
  // at its pose.
  // The caller checks first that the frame was tracked against the map of the current epoch.
  Result<volume::IntegrationStats> integrate(const PosedFrame& frame, const Segmentation* segmentation = nullptr);
  // Fusion thread only: a posed frame that will never be integrated (a newer one of its camera
  // was, or the map was replaced since it was tracked).
  void abandon(const PosedFrame& frame);
  // track() then integrate() on the calling thread: for single-threaded users (tests, eval).
  Result<FrameOutcome> integrateFrame(const Frame& frame, const Segmentation* segmentation = nullptr);
  Result<volume::IntegrationStats> integrateSegmentation(const HistoryEntry& frame, const Segmentation& segmentation);

  // Incremented by every load and reset: frames tracked before belong to a map that is gone.
  uint64_t epoch() const { return epoch_.load(); }

  // Runs `fn(volume)` under the shared lock: for quick reads (sizes, a few voxels).
  template <class Fn>
  auto read(Fn&& fn) const {
    std::shared_lock lock(mutex_);
    return fn(volume_);
  }

  // A read-only copy of the map as of the latest write, for long queries (mesh, objects, region):
  // they run on it without any lock, so they never hold off the fusion thread for longer than the
  // copy however long they take. Copies are shared between queries; after the map changed, one
  // that no query holds any more catches up with the changed leaves (milliseconds after a frame),
  // and only when every copy is still being read is the map copied whole.
  std::shared_ptr<const volume::LabeledVolume> snapshot() const;

  const LabelLegend& legend() const { return options_.legend; }

  Status save(const std::filesystem::path& path, const volume::MapExtraMetadata& extra = {}) const;
  // Replaces the map with a file's content; the map is untouched when the file is missing
  // (kNotFound), bad or its parameters are incompatible with this server's (voxel size,
  // truncation, label rule: kInvalidArgument).
  // Fusion thread only (the server posts admin load/reset to it), like integrateFrame().
  Status load(const std::filesystem::path& path);
  void reset();

  struct Size {
    uint64_t allocated_voxels = 0;
    uint64_t allocated_blocks = 0;
    uint64_t observed_voxels = 0;
    uint64_t memory_bytes = 0;
    uint64_t frames_integrated = 0;
  };
  Size size() const;  // counts the map's voxels: for the status, not for every frame
  // Bytes of the copies snapshot() keeps (a query may still hold one it let go of).
  uint64_t snapshotBytes() const;
  uint64_t framesIntegrated() const;
  // The map's revision (LabeledVolume::revision): raised by every change, so status, query caches
  // and the distance field tell whether the map changed.
  uint64_t revision() const;

  // Called after every write (integrate, label pass, load, reset), on the writing thread, without
  // the map's lock: the distance field updates from here. Set it before the fusion thread starts.
  void setChangeListener(std::function<void()> listener) { on_change_ = std::move(listener); }

 private:
  // Decides the frame's pose (tracking::Tracker) and fills `outcome`.
  Result<tracking::TrackedFrame> choosePose(const Frame& frame, TrackOutcome& outcome);
  // The first frame of a pose-less camera on an empty map defines the world; until it is in the
  // map the next pose-less frames wait for it (they would have nothing to be tracked against, and
  // a second camera would define a second world).
  void firstFrameDone();
  // A panoptic segmentation's instances, after its labels, under the exclusive lock.
  void fuseInstances(const cv::Mat& depth, const Segmentation& segmentation, const PinholeIntrinsics& intrinsics,
                     const Pose& camera_to_world);

  MapperOptions options_;
  // Thread-safe for different cameras (tracker.hpp); reset only under the exclusive lock, which no
  // tracking holds.
  tracking::Tracker tracker_;
  std::atomic<uint64_t> epoch_{0};
  // volume_.framesIntegrated(), written under the exclusive lock: tracking reads it without the
  // lock, which a frame with a pose then never waits for.
  std::atomic<uint64_t> frames_integrated_{0};
  std::mutex first_frame_mutex_;  // held by pose-less tracking while the map is empty
  std::condition_variable first_frame_done_;
  bool first_frame_pending_ = false;  // a world-defining frame is tracked, not integrated yet
  // Writer first: a frame waiting to be fused is not passed over by queries (writer_first_mutex.hpp).
  mutable WriterFirstMutex mutex_;
  volume::LabeledVolume volume_;
  std::function<void()> on_change_;

  mutable std::mutex snapshot_mutex_;  // one snapshot at a time; guards the two below
  // The copies of the map handed to queries, the newest last. A copy no query holds any more is
  // brought up to date from the leaves changed since (LabeledVolume::catchUpWith) instead of being
  // copied whole; a second copy exists only while a query still reads the first.
  mutable std::vector<std::shared_ptr<volume::LabeledVolume>> copies_;
  mutable uint64_t snapshot_revision_ = ~0ull;
};

}  // namespace semfuse::server
