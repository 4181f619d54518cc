#include "semfuse/esdf/map_changes.hpp"

#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::esdf {

namespace {
constexpr int kDim = volume::LabeledVolume::kLeafDim;

// The face layers of the 6 neighbouring leaves, read straight from their buffers.
void copyHalo(const volume::GeometryGrid::TreeType& tree, ChangedLeaf& out) {
  out.halo.fill(std::numeric_limits<float>::quiet_NaN());
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      openvdb::Coord neighbour_origin = out.origin;
      neighbour_origin[axis] += side ? kDim : -kDim;
      const auto* neighbour = tree.probeConstLeaf(neighbour_origin);
      if (!neighbour) continue;
      const int layer = side ? 0 : kDim - 1;  // the neighbour's layer that touches this leaf
      const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
      for (int a = 0; a < kDim; ++a)
        for (int b = 0; b < kDim; ++b) {
          openvdb::Coord local(0, 0, 0);
          local[axis] = layer;
          local[u] = a;
          local[v] = b;
          const openvdb::Index n = (local.x() << 6) | (local.y() << 3) | local.z();
          if (neighbour->isValueOn(n))
            out.halo[ChangedLeaf::haloIndex(axis, side == 1, a, b)] = volume::unpackTsdf(neighbour->getValue(n));
        }
    }
}
}  // namespace

MapChanges copyChanges(const volume::LabeledVolume& map, uint64_t revision) {
  volume::LabeledVolume::LeafChanges changed = map.changesSince(revision);
  if (!changed.all) {
    // A site depends on its 6-neighbours: a change at a leaf's face can make or unmake sites in the
    // face-adjacent leaves, which are therefore classified again too.
    openvdb::MaskTree keys;
    openvdb::tree::ValueAccessor<openvdb::MaskTree> marks(keys);
    const auto& geometry = map.geometryGrid().tree();
    for (const openvdb::Coord& origin : changed.leaves) {
      marks.setValueOn(origin);
      for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
          openvdb::Coord neighbour = origin;
          neighbour[axis] += side * volume::LabeledVolume::kLeafDim;
          if (geometry.probeConstLeaf(neighbour)) marks.setValueOn(neighbour);
        }
    }
    changed.leaves.clear();
    for (auto it = keys.cbeginValueOn(); it; ++it)
      if (((it.getCoord().x() | it.getCoord().y() | it.getCoord().z()) & (volume::LabeledVolume::kLeafDim - 1)) == 0)
        changed.leaves.push_back(it.getCoord());
  }
  MapChanges changes;
  changes.revision = changed.revision;
  changes.all = changed.all;
  changes.voxel_size = map.voxelSize();
  changes.leaves.resize(changed.leaves.size());
  const auto& tree = map.geometryGrid().tree();
  const volume::FreeSpaceGrid* free_space = map.freeSpaceGrid();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.leaves.size(), 32),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        ChangedLeaf& out = changes.leaves[i];
                        out.origin = changed.leaves[i];
                        if (free_space) {
                          // Wholly free leaves are tiles; partly free ones mask leaves.
                          if (const auto* mask = free_space->tree().probeConstLeaf(out.origin)) {
                            for (openvdb::Index n = 0; n < volume::LabeledVolume::kLeafVoxels; ++n)
                              out.observed_free[n] = mask->isValueOn(n);
                          } else if (free_space->tree().isValueOn(out.origin)) {
                            out.observed_free.fill(true);
                          }
                        }
                        const auto* leaf = tree.probeConstLeaf(out.origin);
                        out.has_geometry = leaf != nullptr;
                        if (!leaf) continue;
                        copyHalo(tree, out);
                        for (openvdb::Index n = 0; n < volume::LabeledVolume::kLeafVoxels; ++n) {
                          out.voxels[n] = leaf->getValue(n);
                          out.observed[n] = leaf->isValueOn(n);
                        }
                      }
                    });
  return changes;
}

}  // namespace semfuse::esdf
