#pragma once
// SurfaceCache: the labeled surface (surface_voxels.hpp) of a map that changes, re-extracted only
// where it changed since the last call.
//
// A leaf's surface voxels depend on the leaf, its six face neighbours (the TSDF one voxel across)
// and its instance evidence. The cache keeps each leaf's voxels and the map revision they are up
// to date with; given a later snapshot of the same map it re-scans the leaves that
// LabeledVolume::changesSince() names and their face neighbours, and reuses the others. The
// surface it returns is extractSurface()'s, voxel for voxel and in the same order. A map that was
// cleared or replaced since (changesSince says `all`) is scanned whole.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>

#include "semfuse/core/legend.hpp"
#include "semfuse/objects/surface_voxels.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::objects {

class SurfaceCache {
 public:
  explicit SurfaceCache(LabelLegend legend, int min_instance_evidence = 2);

  // The surface of `volume`. Every call must hand a snapshot of one map, each as new as the last
  // or newer (the server's snapshots are); an older one is scanned whole.
  SurfaceVoxels update(const volume::LabeledVolume& volume);
  // Forgets everything: the next update scans the whole map.
  void clear();

  // Leaves the last update scanned (the rest came from the cache).
  std::size_t lastScannedLeaves() const { return last_scanned_; }

 private:
  struct CoordHash {
    std::size_t operator()(const openvdb::Coord& c) const { return c.hash<20>(); }
  };
  LabelLegend legend_;
  int min_instance_evidence_;
  std::optional<uint64_t> revision_;  // of the map the cache is up to date with; none: empty
  std::unordered_map<openvdb::Coord, std::vector<SurfaceVoxel>, CoordHash> by_leaf_;  // by leaf origin
  std::size_t last_scanned_ = 0;
};

}  // namespace semfuse::objects
