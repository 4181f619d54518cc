#include "semfuse/esdf/map_changes.hpp"

#include <algorithm>
#include <limits>
#include <optional>

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

openvdb::Coord scaled(const openvdb::Coord& c, int factor) { return {c.x() * factor, c.y() * factor, c.z() * factor}; }

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// The field leaves (origins in field voxels) whose voxels or halo read a map voxel of the changed
// map leaves: field voxel c reads map voxel stride * c, the halo reaches one voxel past each face.
std::vector<openvdb::Coord> fieldLeavesReading(const std::vector<openvdb::Coord>& map_leaves, int stride) {
  openvdb::MaskTree keys;
  openvdb::tree::ValueAccessor<openvdb::MaskTree> marks(keys);
  for (const openvdb::Coord& origin : map_leaves) {
    // Field voxels c with stride * c in [origin, origin + kDim), widened by the halo's one voxel.
    openvdb::Coord lo, hi;
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = floorDiv(floorDiv(origin[axis] + stride - 1, stride) - 1, kDim);
      hi[axis] = floorDiv(floorDiv(origin[axis] + kDim - 1, stride) + 1, kDim);
    }
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y)
        for (int z = lo.z(); z <= hi.z(); ++z) marks.setValueOn(openvdb::Coord(x, y, z));
  }
  std::vector<openvdb::Coord> leaves;
  for (auto it = keys.cbeginValueOn(); it; ++it) leaves.push_back(scaled(it.getCoord(), kDim));
  return leaves;
}

// The map's grids through accessors of one task: neighbouring map leaves share their internal
// nodes, so most look-ups stop at a cached node.
struct MapReaders {
  explicit MapReaders(const volume::LabeledVolume& map) : geometry(map.geometryGrid().tree()) {
    if (map.freeSpaceGrid()) free_space.emplace(map.freeSpaceGrid()->tree());
  }
  openvdb::tree::ValueAccessor<const volume::GeometryGrid::TreeType> geometry;
  std::optional<openvdb::tree::ValueAccessor<const volume::FreeSpaceGrid::TreeType>> free_space;  // none observed
};

// One field leaf read from the map at every stride-th voxel, its halo included. The field leaf's
// own samples are read map leaf by map leaf (a field leaf lies over stride^3 whole map leaves, its
// origin being a multiple of 8 field voxels), each looked up once; the halo's through an accessor.
void sampleLeaf(MapReaders& map, int stride, ChangedLeaf& out) {
  const openvdb::Coord base = scaled(out.origin, stride);  // map voxel under field voxel (0, 0, 0)
  // The field coordinates along an axis whose samples lie in the map leaf at `first` map voxels
  // from the base: stride * c in [first, first + kDim).
  const auto samplesFrom = [&](int first) { return (first + stride - 1) / stride; };
  const auto samplesTo = [&](int first) { return std::min(kDim, (first + kDim + stride - 1) / stride); };
  for (int i = 0; i < stride; ++i)
    for (int j = 0; j < stride; ++j)
      for (int k = 0; k < stride; ++k) {
        const openvdb::Coord leaf_origin = base.offsetBy(i * kDim, j * kDim, k * kDim);
        const auto* leaf = map.geometry.probeConstLeaf(leaf_origin);
        // Observed free space: a mask leaf, or a tile where the whole map leaf is free.
        const auto* free_leaf = map.free_space ? map.free_space->probeConstLeaf(leaf_origin) : nullptr;
        const bool free_tile = map.free_space && !free_leaf && map.free_space->isValueOn(leaf_origin);
        if (!leaf && !free_leaf && !free_tile) continue;
        for (int x = samplesFrom(i * kDim); x < samplesTo(i * kDim); ++x)
          for (int y = samplesFrom(j * kDim); y < samplesTo(j * kDim); ++y)
            for (int z = samplesFrom(k * kDim); z < samplesTo(k * kDim); ++z) {
              const int n = (x << 6) | (y << 3) | z;
              const auto in_leaf = static_cast<openvdb::Index>(
                  ((x * stride - i * kDim) << 6) | ((y * stride - j * kDim) << 3) | (z * stride - k * kDim));
              if (leaf && leaf->isValueOn(in_leaf)) {
                out.voxels[n] = leaf->getValue(in_leaf);
                out.observed[n] = true;
                out.has_geometry = true;
              }
              out.observed_free[n] = free_tile || (free_leaf && free_leaf->isValueOn(in_leaf));
            }
      }
  const auto sample = [&](int x, int y, int z) { return scaled(out.origin.offsetBy(x, y, z), stride); };
  out.halo.fill(std::numeric_limits<float>::quiet_NaN());
  ChangedLeaf::forEachHaloVoxel([&](int i, int x, int y, int z) {
    volume::PackedVoxel packed;
    if (!map.geometry.probeValue(sample(x, y, z), packed)) return;
    out.halo[i] = volume::unpackTsdf(packed);
    out.has_geometry = true;
  });
}

MapChanges copySampledChanges(const volume::LabeledVolume& map, uint64_t revision, int stride) {
  const volume::LabeledVolume::LeafChanges changed = map.changesSince(revision);
  MapChanges changes;
  changes.revision = changed.revision;
  changes.all = changed.all;
  changes.voxel_size = map.voxelSize() * stride;
  const std::vector<openvdb::Coord> origins = fieldLeavesReading(changed.leaves, stride);
  changes.leaves.resize(origins.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      MapReaders readers(map);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        changes.leaves[i].origin = origins[i];
                        sampleLeaf(readers, stride, changes.leaves[i]);
                      }
                    });
  return changes;
}

}  // namespace

MapChanges copyChanges(const volume::LabeledVolume& map, uint64_t revision, int stride) {
  if (stride > 1) return copySampledChanges(map, revision, stride);
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
