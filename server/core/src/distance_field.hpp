#pragma once
// DistanceField: the server's distance field (semfuse::esdf), kept up to date from the map on a
// thread of its own (sf-esdf), off the fusion thread's critical path. The Mapper tells it when
// the map changed; the thread copies the changed leaves under the map's shared lock (the only
// time it holds it, under a millisecond at 5 cm), then updates the field under the field's own
// lock, taken per slice of 256 changed leaves so that queries and stop() wait for a slice at most,
// not for a whole update. Changes that arrive during an update are taken together by the next one, so a slow update
// makes the field lag (reported as lag_revisions in stats()) rather than queue work. Queries read
// the field under its shared lock; a load or reset of the map makes the next update a rebuild.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <thread>
#include <vector>

#include "distance_source.hpp"
#include "mapper.hpp"
#include "semfuse/esdf/esdf_map.hpp"
#include "semfuse/esdf/semantic_distance.hpp"
#include "stage_timings.hpp"

namespace semfuse::server {

class DistanceField final : public DistanceSource {
 public:
  // The field's voxel is params.fieldVoxel() of the mapper's voxel size and truncation.
  DistanceField(const Mapper& mapper, esdf::EsdfParams params);
  ~DistanceField();
  DistanceField(const DistanceField&) = delete;
  DistanceField& operator=(const DistanceField&) = delete;

  // Where each update's time goes (before start()).
  void recordTimesIn(StageTimings& timings) { timings_ = &timings; }
  void start();
  void stop();    // finishes the slice of the update in hand
  void notify();  // the map changed (any thread)

  // Runs fn(field) under the field's shared lock.
  template <class Fn>
  auto readField(Fn&& fn) const {
    std::shared_lock lock(mutex_);
    return fn(field_);
  }
  void read(const std::function<void(const esdf::EsdfMap&)>& fn) const override {
    readField([&](const esdf::EsdfMap& field) {
      fn(field);
      return 0;
    });
  }

  // The surface points of `labels` in a KD-tree, built on first use and kept until the field's
  // labeled surfaces change (a few recent label sets are kept).
  std::shared_ptr<const esdf::SurfaceIndex> surfaceIndex(std::vector<LabelId> labels) const override;

  // Until the field reflects the map as of now (for tests and the bench); false on timeout.
  bool waitUntilCurrent(std::chrono::milliseconds timeout) const;

  uint64_t revision() const { return revision_.load(); }  // the map revision the field reflects

  struct Stats {
    uint64_t updates = 0;
    double last_update_ms = 0.0;
    uint64_t revision = 0;  // the map revision the field reflects
    std::size_t known_voxels = 0;
    std::size_t memory_bytes = 0;
  };
  Stats stats() const;

 private:
  DistanceField(const Mapper& mapper, esdf::EsdfParams params, const volume::VolumeParams& map);

  void run();
  void updateOnce();

  const Mapper& mapper_;
  mutable std::shared_mutex mutex_;  // guards field_
  esdf::EsdfMap field_;
  const int stride_;  // map voxels per field voxel

  mutable std::mutex wake_mutex_;
  mutable std::condition_variable wake_;
  bool pending_ = false;  // under wake_mutex_
  std::atomic<bool> running_{false};
  std::thread thread_;

  StageTimings* timings_ = nullptr;
  std::atomic<uint64_t> updates_{0};
  std::atomic<double> last_update_ms_{0.0};
  std::atomic<uint64_t> revision_{0};

  // Semantic index cache: sorted label set -> (surfaces revision, index).
  struct CachedIndex {
    uint64_t surfaces_revision = 0;
    std::shared_ptr<const esdf::SurfaceIndex> index;
  };
  mutable std::mutex cache_mutex_;
  mutable std::map<std::vector<LabelId>, CachedIndex> cache_;
};

}  // namespace semfuse::server
