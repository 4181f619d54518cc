#pragma once
// MapUpdater: keeps the live mesh (MeshBlockStore) up to date with the map and hands each round's
// changed blocks to a sink that publishes them (server/dds/map_update_publisher.hpp), on its own
// thread (sf-map-updates) at --map-updates.rate, off the fusion thread's path.
//
// A round asks the volume which leaves changed since the revision the store is up to date with
// (LabeledVolume::changesSince), copies the voxels of the blocks that read them
// (render/mesh_blocks.hpp) in batches under the map's shared lock, meshes the copies without it,
// keeps the blocks whose mesh differs, and publishes them as one update, in parts when large.
// Blocks are those of the live mesh's lattice (--map-updates.voxel-size). The work follows the change, not the map: a
// block is meshed only when one of the eight leaves it reads was written. After a clear or a load (`all`) the store
// starts over and every block is meshed.
//
// Nobody listening (no reader of the sink's topics, no map_blocks request for
// --map-updates.idle-after) costs nothing: rounds are skipped, and the first round after that
// catches up with everything that changed meanwhile.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>

#include "map_access.hpp"
#include "map_update_config.hpp"
#include "mesh_block_store.hpp"
#include "periodic_thread.hpp"
#include "semfuse/core/map_blocks.hpp"
#include "stage_timings.hpp"

namespace semfuse::server {

class MapUpdater {
 public:
  class Sink {
   public:
    virtual ~Sink() = default;
    // Whether anyone follows the live mesh now.
    virtual bool listening() const = 0;
    // One part of an update, on the updater's thread.
    virtual void publish(const MapUpdate& update) = 0;
  };

  struct Round {
    bool skipped = false;  // nobody listening
    std::size_t blocks_meshed = 0;
    std::size_t blocks_sent = 0;  // with a changed mesh
    std::size_t parts = 0;        // samples published (0 when nothing changed)
    double locked_ms = 0;         // time the map's shared lock was held, over all batches
    double total_ms = 0;
  };

  struct Totals {
    uint64_t rounds = 0, skipped = 0, updates = 0, parts = 0, blocks_meshed = 0, blocks_sent = 0;
    uint64_t payload_bytes = 0;  // of the blocks sent
    double locked_ms = 0, busy_ms = 0;
  };

  MapUpdater(const MapAccess& map, const MapUpdateConfig& config, Sink& sink);
  ~MapUpdater();

  // Where each round's time goes (before start()).
  void recordTimesIn(StageTimings& timings) { timings_ = &timings; }
  void start();  // the thread; nothing when the rate is 0
  void stop();

  // One round now (the thread's work; tests call it directly).
  Round update();
  // A map_blocks request came: follow the map for the next idle_after_s even without readers.
  void touch();

  const MeshBlockStore& store() const { return store_; }
  Totals totals() const;

 private:
  bool wanted() const;
  std::size_t publishParts(std::vector<MeshBlock> blocks, bool cleared);

  const MapAccess& map_;
  MapUpdateConfig config_;
  Sink& sink_;
  MeshBlockStore store_;
  uint64_t published_revision_ = 0;  // revision of the last update published (0 = none)
  std::atomic<int64_t> touched_at_ns_{0};

  StageTimings* timings_ = nullptr;
  mutable std::mutex totals_mutex_;
  Totals totals_;

  PeriodicThread rounds_;  // last: stops before what its rounds use goes
};

}  // namespace semfuse::server
