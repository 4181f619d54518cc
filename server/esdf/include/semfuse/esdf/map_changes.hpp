#pragma once
// What the distance field needs from the map for the leaves that changed: a copy of each changed
// geometry leaf (packed voxels and active mask) and which of its voxels are observed free space.
// Taking the copy is the only part that reads the map, so a server holds the map's lock for the
// copy alone (a few hundred microseconds per frame) and updates the distance field without it.
#include <array>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>

#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::esdf {

struct ChangedLeaf {
  openvdb::Coord origin;
  bool has_geometry = false;  // the map holds a geometry leaf here
  // Per voxel, index = OpenVDB leaf offset: the packed TSDF voxel, whether the TSDF observed it,
  // whether it lies in observed free space.
  std::array<volume::PackedVoxel, volume::LabeledVolume::kLeafVoxels> voxels{};
  std::array<bool, volume::LabeledVolume::kLeafVoxels> observed{};
  std::array<bool, volume::LabeledVolume::kLeafVoxels> observed_free{};
  // The TSDF of the voxels just outside the leaf's 6 faces (NaN where unobserved), for the sign
  // changes across them: face f = 2 * axis + (0 for the minimum side, 1 for the maximum), then
  // the other two local coordinates in axis order (haloIndex).
  std::array<float, 6 * 64> halo{};

  static int haloIndex(int axis, bool max_side, int a, int b) {
    return (2 * axis + (max_side ? 1 : 0)) * 64 + a * 8 + b;
  }
  // Calls fn(index in `halo`, x, y, z) for every halo voxel, (x, y, z) its local coordinates in
  // the leaf's frame (one of them -1 or 8).
  template <class Fn>
  static void forEachHaloVoxel(Fn&& fn) {
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side) {
        const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
        for (int a = 0; a < 8; ++a)
          for (int b = 0; b < 8; ++b) {
            int at[3];
            at[axis] = side ? 8 : -1;
            at[u] = a;
            at[v] = b;
            fn(haloIndex(axis, side == 1, a, b), at[0], at[1], at[2]);
          }
      }
  }
};

struct MapChanges {
  uint64_t revision = 0;            // the map's revision the changes bring the distance field up to
  bool all = false;                 // the map was cleared or replaced: rebuild from these leaves alone
  double voxel_size = 0.0;          // the field's voxel: the map's times the stride
  std::vector<ChangedLeaf> leaves;  // in the field's voxels
};

// The leaves changed since `revision` (LabeledVolume::changesSince), copied. Run it under the
// map's read lock; parallel over leaves. With a stride above 1 (EsdfParams::stride) the leaves
// are the field's: field voxel (i, j, k) is the map's voxel (stride i, stride j, stride k), and a
// field leaf is copied when one of its voxels or of its halo lies in a changed map leaf.
MapChanges copyChanges(const volume::LabeledVolume& map, uint64_t revision, int stride = 1);

}  // namespace semfuse::esdf
