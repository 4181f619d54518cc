#pragma once
// Mapper: the one object that owns the map (nvblox-style facade). The fusion thread is its only
// writer: integrateFrame() picks the pose (given, refined or tracked), fuses depth, colour and
// labels; integrateSegmentation() adds a late segmentation's label evidence. Queries read under a
// shared lock, so they run concurrently with each other and wait only for the write in progress.
// Saving copies the volume under the shared lock and writes the copy without holding it.
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

struct FrameOutcome {
  bool integrated = false;
  PoseState pose_state = PoseState::kGiven;
  Pose camera_to_world = Pose::Identity();
  float inlier_ratio = 1.0f;
  float residual = 0.0f;
  uint32_t iterations = 0;
  double track_ms = 0.0;
  double integrate_ms = 0.0;
  std::string lost_reason;  // why tracking gave up (pose_state == kLost)
  // The camera's tracking after this frame: frames the current loss has lasted (0 while
  // tracking) and times a keyframe found it again or placed it.
  uint64_t frames_since_lost = 0;
  uint64_t relocalisations = 0;
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

  // Fusion thread only. Errors: bad input (sizes, intrinsics, a pose that is not rigid). A frame
  // the tracker cannot place (lost, or a pose-less camera no keyframe has placed yet) is no error:
  // the outcome says it was not integrated and why.
  Result<FrameOutcome> integrateFrame(const Frame& frame, const Segmentation* segmentation = nullptr);
  Result<volume::IntegrationStats> integrateSegmentation(const HistoryEntry& frame, const Segmentation& segmentation);

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
  Size size() const;
  // Incremented by every write; lets status and query caches tell whether the map changed.
  uint64_t revision() const;

  // Called after every write (integrate, label pass, load, reset), on the writing thread, without
  // the map's lock: the distance field updates from here. Set it before the fusion thread starts.
  void setChangeListener(std::function<void()> listener) { on_change_ = std::move(listener); }

 private:
  // Decides the frame's pose (tracking::Tracker) and fills `outcome`.
  Result<tracking::TrackedFrame> choosePose(const Frame& frame, FrameOutcome& outcome);

  MapperOptions options_;
  tracking::Tracker tracker_;  // fusion thread only
  // Writer first: a frame waiting to be fused is not passed over by queries (writer_first_mutex.hpp).
  mutable WriterFirstMutex mutex_;
  volume::LabeledVolume volume_;
  uint64_t revision_ = 0;  // guarded by mutex_
  std::function<void()> on_change_;

  mutable std::mutex snapshot_mutex_;  // one snapshot at a time; guards the two below
  // The copies of the map handed to queries, the newest last. A copy no query holds any more is
  // brought up to date from the leaves changed since (LabeledVolume::catchUpWith) instead of being
  // copied whole; a second copy exists only while a query still reads the first.
  mutable std::vector<std::shared_ptr<volume::LabeledVolume>> copies_;
  mutable uint64_t snapshot_revision_ = ~0ull;
};

}  // namespace semfuse::server
