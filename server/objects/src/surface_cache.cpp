#include "semfuse/objects/surface_cache.hpp"

#include <algorithm>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "leaf_scanner.hpp"

namespace semfuse::objects {
namespace {

using detail::GeometryLeaf;
using detail::kLeafDim;

// The leaves whose surface a change to these leaves can touch: themselves and their face
// neighbours, each once.
std::vector<openvdb::Coord> withFaceNeighbours(const std::vector<openvdb::Coord>& changed) {
  std::vector<openvdb::Coord> out;
  out.reserve(7 * changed.size());
  for (const openvdb::Coord& origin : changed) {
    out.push_back(origin);
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {-1, 1}) {
        openvdb::Coord neighbour = origin;
        neighbour[axis] += side * kLeafDim;
        out.push_back(neighbour);
      }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace

SurfaceCache::SurfaceCache(LabelLegend legend, int min_instance_evidence)
    : legend_(std::move(legend)), min_instance_evidence_(min_instance_evidence) {}

void SurfaceCache::clear() {
  revision_.reset();
  by_leaf_.clear();
}

SurfaceVoxels SurfaceCache::update(const volume::LabeledVolume& volume) {
  const auto& tree = volume.geometryGrid().tree();
  std::vector<const GeometryLeaf*> leaves;
  leaves.reserve(tree.leafCount());
  tree.getNodes(leaves);

  // The leaves to scan: all of them, or those a change since the last update can touch.
  std::vector<const GeometryLeaf*> to_scan;
  const volume::LabeledVolume::LeafChanges changes =
      revision_ && *revision_ <= volume.revision() ? volume.changesSince(*revision_)
                                                   : volume::LabeledVolume::LeafChanges{volume.revision(), true, {}};
  if (changes.all) {
    by_leaf_.clear();
    to_scan = leaves;
  } else {
    for (const openvdb::Coord& origin : withFaceNeighbours(changes.leaves)) {
      if (const GeometryLeaf* leaf = tree.probeConstLeaf(origin)) to_scan.push_back(leaf);
      else by_leaf_.erase(origin);
    }
  }

  // Scanned in parallel into slots made beforehand (the map does not grow concurrently).
  std::vector<std::vector<SurfaceVoxel>*> slots(to_scan.size());
  for (std::size_t i = 0; i < to_scan.size(); ++i) slots[i] = &by_leaf_[to_scan[i]->origin()];
  const detail::CountedLabels counted(legend_);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, to_scan.size(), 32),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      detail::LeafScanner scanner(volume, counted, min_instance_evidence_);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        slots[i]->clear();
                        scanner.scan(*to_scan[i], *slots[i]);
                      }
                    });
  last_scanned_ = to_scan.size();
  revision_ = changes.revision;

  // In the tree's order of leaves, as extractSurface() gives them.
  std::vector<const std::vector<SurfaceVoxel>*> in_order;
  in_order.reserve(leaves.size());
  std::size_t total = 0;
  for (const GeometryLeaf* leaf : leaves) {
    const auto found = by_leaf_.find(leaf->origin());
    if (found == by_leaf_.end() || found->second.empty()) continue;
    in_order.push_back(&found->second);
    total += found->second.size();
  }
  std::vector<SurfaceVoxel> voxels;
  voxels.reserve(total);
  for (const auto* leaf : in_order) voxels.insert(voxels.end(), leaf->begin(), leaf->end());
  SurfaceVoxels surface(volume.voxelSize(), std::move(voxels));
  surface.setInstancePairsSeenApart(volume.instancePairsSeenApart());
  return surface;
}

}  // namespace semfuse::objects
