#pragma once
// The raise and lower waves of an update (esdf/README.md, "How it is updated"). The update's
// classification queues their seeds (addRaise, addLower, addOrphan); run() clears what pointed at
// vanished sites, then hands sites outwards nearest first until nothing improves.
//
// Waves on the free side also cross the unknown voxels of the field's leaves (inactive, but
// holding a site like any other voxel): a distance is the straight-line distance to the nearest
// observed surface, and a pocket nobody looked into must not make the wave go round it. Queries
// never read those voxels.
//
// One object lives as long as its field, so the queues keep their capacity from one update to
// the next.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "leaf_neighbourhood.hpp"
#include "semfuse/esdf/esdf_map.hpp"

namespace semfuse::esdf::detail {

class Waves {
 public:
  Waves(FieldTree& tree, float max_voxels);

  // A voxel that became a site or moved nearer the surface: its site spreads from it.
  void addLower(const VoxelRef& voxel) { seeds_.push_back(voxel); }
  // A site that vanished, changed side or moved away: the voxels that point at it are cleared.
  void addRaise(const VoxelRef& site) { raise_.push_back({site, site.coord()}); }
  // A voxel without a site: its neighbours offer theirs.
  void addOrphan(const VoxelRef& voxel) { orphans_.push_back(voxel); }

  // Raise, then lower; adds to stats' cleared, relaxed and popped.
  void run(UpdateStats& stats);

 private:
  struct RaiseItem {
    VoxelRef from;
    openvdb::Coord site;
  };
  struct Queued {
    VoxelRef voxel;
    float distance;  // the voxel's distance when queued: larger than now means queued again since
    uint64_t order;  // where a bucket puts it: by leaf origin, then offset (queueOrder)
  };

  void raise(UpdateStats& stats);
  void seedOrphans();
  void lower(UpdateStats& stats);
  void relax(Queued item, UpdateStats& stats);
  void push(const VoxelRef& voxel, float distance);
  void pushNeighboursWithSites(const VoxelRef& voxel, bool inside);

  float max_voxels_;
  LeafNeighbourhood neighbourhood_;
  // The sites, read through an accessor of their own: a site is often leaves away, and reading
  // it through the neighbourhood's would evict the leaves a voxel's neighbours are read from.
  openvdb::tree::ValueAccessor<const FieldTree> sites_;
  std::vector<VoxelRef> seeds_, orphans_;
  std::vector<VoxelRef> marked_;  // the voxels seedOrphans queued, marked until it ends
  std::vector<RaiseItem> raise_;
  std::vector<std::vector<Queued>> buckets_;
  std::size_t current_ = 0;  // the bucket lower() is working through
};

}  // namespace semfuse::esdf::detail
