#pragma once
// ObjectTracker: the map's objects as the server keeps them. Given a snapshot of the map it
// extracts the labeled surface (re-scanning only the leaves changed since its last snapshot,
// surface_cache.hpp), groups it (grouping.hpp), matches the groups to the objects of
// the last update (object_registry.hpp), measures them (object_figures.hpp) and finds the frames
// that saw them (view_index.hpp); the same snapshot again costs nothing. Every update that
// changes something is numbered and its events go to the listener. Thread-safe: one update at a
// time, answers shared between callers.
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/object_events.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/objects/object_figures.hpp"
#include "semfuse/objects/object_params.hpp"
#include "semfuse/objects/object_registry.hpp"
#include "semfuse/objects/surface_cache.hpp"
#include "semfuse/objects/view_index.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::objects {

struct TrackedObject {
  uint32_t id = 0;
  LabelId label = kUnlabeled;
  bool fragment = false;
  uint32_t instance = 0;  // the panoptic instance most of it carries, 0 = none
  ObjectFigures figures;
  std::vector<FrameRef> frames;  // most of its surface first
  uint32_t frame_count = 0;
};

// The objects of one snapshot of the map.
struct ObjectSet {
  std::vector<TrackedObject> objects;             // objects largest first, then fragments
  std::shared_ptr<const openvdb::Int32Tree> ids;  // object id of every surface voxel
  Eigen::Vector3d up = Eigen::Vector3d::Zero();   // the up the grouping used (zero: unknown)
  uint64_t update = 0;                            // the update that made it
  double voxel_size = 0.0;                        // of the map it was grouped from, metres
  const TrackedObject* find(uint32_t id) const;
};

// The area-weighted mean normal of the surface labeled with a class named "floor" in the legend,
// when there is at least 0.25 m^2 of it and its normals agree (mean length >= 0.7).
std::optional<Eigen::Vector3d> upFromFloor(const SurfaceVoxels& surface, const LabelLegend& legend);

// Where the last update's time went, milliseconds of wall clock: for the benchmark.
struct UpdateTimes {
  double surface = 0.0;   // the surface from the cache and the changed leaves
  double grouping = 0.0;  // groupSurface(), with the up from the floor
  double ids = 0.0;       // matching to the last update's objects
  double figures = 0.0;   // measureGroups() and the frames that saw each object
};

class ObjectTracker {
 public:
  static constexpr std::size_t kFramesPerObject = 16;

  ObjectTracker(ObjectParams params, LabelLegend legend, double voxel_size);

  // The objects of `map`; regroups only when `map` is not the snapshot of the last call at the
  // same revision, and only looks up the frames again when frames were recorded since. Every
  // call hands a snapshot of one map, as new as the last or newer (surface_cache.hpp).
  std::shared_ptr<const ObjectSet> objectsOf(const std::shared_ptr<const volume::LabeledVolume>& map);

  // The last set when it answered for a map at most max_age older than now, or else the objects
  // of map() (a snapshot taken once this call has the update's lock): a caller that waited for an
  // update in progress takes its set when it is recent enough, instead of grouping again.
  std::shared_ptr<const ObjectSet> recentOrOf(std::chrono::duration<double> max_age,
                                              const std::function<std::shared_ptr<const volume::LabeledVolume>()>& map);

  // The set of the last call, and when that call began: the map it answers for was at least as
  // new as the map then. Null before the first call. Does not wait for an update in progress.
  struct Latest {
    std::shared_ptr<const ObjectSet> set;
    std::chrono::steady_clock::time_point current_at;
  };
  Latest latest() const {
    std::lock_guard lock(latest_mutex_);
    return latest_;
  }

  // Called with the events of every update that has any, under the update's lock (so in order).
  void setListener(std::function<void(const ObjectEvents&)> listener);

  // Frames, as the fusion thread fuses them (view_index.hpp).
  void recordView(const Frame& frame, const Pose& camera_to_world, float min_depth, float max_depth);
  // The map was reset or replaced: the frames that saw it are gone.
  void forgetViews() { views_.clear(); }

  const ObjectParams& params() const { return params_; }
  // Leaves the last update scanned for surface (the others' surface was cached).
  std::size_t lastScannedLeaves() const {
    std::lock_guard lock(mutex_);
    return surface_cache_.lastScannedLeaves();
  }
  UpdateTimes lastUpdateTimes() const {
    std::lock_guard lock(mutex_);
    return last_times_;
  }

 private:
  // objectsOf() with the update's lock held.
  std::shared_ptr<const ObjectSet> update(const std::shared_ptr<const volume::LabeledVolume>& map,
                                          std::chrono::steady_clock::time_point called_at);

  ObjectParams params_;
  LabelLegend legend_;
  ViewIndex views_;
  mutable std::mutex mutex_;  // one update at a time; guards the members below
  SurfaceCache surface_cache_;
  ObjectRegistry registry_;
  // The map the last set was grouped from, and its revision: the server brings an idle copy of
  // the map up to date in place, so the same copy can come back with other content.
  std::weak_ptr<const volume::LabeledVolume> last_map_;
  uint64_t last_revision_ = 0;
  uint64_t last_views_ = 0;  // the view index's version the last set's frames were taken at
  std::shared_ptr<const ObjectSet> last_;
  uint64_t updates_ = 0;
  UpdateTimes last_times_;
  mutable std::mutex latest_mutex_;  // guards latest_ alone, so that latest() never waits for an update
  Latest latest_;
  std::function<void(const ObjectEvents&)> listener_;
};

}  // namespace semfuse::objects
