#pragma once
// EsdfMap: the Euclidean signed distance field of a LabeledVolume, kept up to date from the
// leaves that changed (map_changes.hpp), and the labeled surface points the semantic queries
// search (label_surfaces.hpp). Free functions answer the queries (distance_queries.hpp,
// semantic_distance.hpp).
//
// How it works (esdf/README.md has the details and figures): every observed voxel is known, on
// the inside or the free side of the surface by its TSDF sign (voxels of observed free space are
// free); observed voxels with a 6-neighbour across the surface are surface sites. Each known voxel
// keeps the offset to its nearest site on its own side (esdf_voxel.hpp), found by a wavefront from
// the sites over 26-neighbours, within the maximum distance (as voxblox and nvblox propagate
// "parents"). An update re-classifies the voxels of the changed leaves; where a site vanished or
// moved away, a raise wave clears the voxels that pointed at it, and a lower wave from the new
// sites and from the edge of the cleared region fills them again. Unknown space stays unknown:
// the field never propagates into a voxel nobody observed.
//
// Not thread-safe: one writer (apply), readers under the caller's lock.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "semfuse/esdf/esdf_params.hpp"
#include "semfuse/esdf/esdf_voxel.hpp"
#include "semfuse/esdf/label_surfaces.hpp"
#include "semfuse/esdf/map_changes.hpp"

namespace semfuse::esdf {
namespace detail {
class Waves;
}  // namespace detail

struct UpdateStats {
  std::size_t leaves = 0;         // changed leaves processed
  std::size_t sites_added = 0;    // voxels that became sites (or moved closer to the surface)
  std::size_t sites_removed = 0;  // sites that vanished, flipped side or moved away
  std::size_t cleared = 0;        // voxels cleared by raise waves
  std::size_t relaxed = 0;        // voxels whose nearest site the lower wave changed
  std::size_t popped = 0;         // voxels the lower wave took from its queue
  bool rebuilt = false;           // the map was cleared or replaced: everything recomputed
};

class EsdfMap {
 public:
  EsdfMap(double voxel_size, EsdfParams params = {});
  ~EsdfMap();
  EsdfMap(const EsdfMap&) = delete;
  EsdfMap& operator=(const EsdfMap&) = delete;

  // Brings the field up to the changes' revision. Changes must come in order (copyChanges with
  // this map's revision()); changes.all clears the field first.
  UpdateStats apply(const MapChanges& changes);
  void clear();

  uint64_t revision() const { return revision_; }  // the map revision the field is up to date with
  const EsdfGrid& grid() const { return *grid_; }
  const EsdfParams& params() const { return params_; }
  double voxelSize() const { return voxel_size_; }
  float maxDistanceVoxels() const { return max_voxels_; }
  const LabelSurfaces& surfaces() const { return surfaces_; }

  std::size_t knownVoxels() const { return grid_->tree().activeVoxelCount(); }
  std::size_t memoryBytes() const { return grid_->memUsage() + surfaces_.memoryBytes(); }

 private:
  double voxel_size_;
  EsdfParams params_;
  float max_voxels_;
  EsdfGrid::Ptr grid_;
  LabelSurfaces surfaces_;
  std::unique_ptr<detail::Waves> waves_;  // after grid_: its accessors go before the tree
  uint64_t revision_ = 0;
};

}  // namespace semfuse::esdf
