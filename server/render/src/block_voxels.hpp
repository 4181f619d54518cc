#pragma once
// The voxels a mesh block reads, in place: [0, 10)^3 from the block's origin, which is its own
// leaf and two layers of the seven leaves above it (+x, +y, +z and their combinations). Colour
// leaves are looked up separately, so that a block found to have no surface never probes them.
// Internal to the block mesher (mesh_blocks.cpp).
#include <openvdb/openvdb.h>

#include "mesh_cells.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

inline constexpr int kBlockSpan = kLeafDim + 2;  // voxels per side a block reads

class BlockVoxels {
 public:
  // False when the block's own leaf is not allocated: then none of its cells is observed.
  bool gather(const volume::GeometryGrid::ConstUnsafeAccessor& geometry, const openvdb::Coord& origin) {
    gatherLeaves(geometry, origin, voxels_);
    return voxels_[0][0][0] != nullptr;
  }
  void gatherColors(const volume::ColorGrid::ConstUnsafeAccessor& colors, const openvdb::Coord& origin) {
    gatherLeaves(colors, origin, colors_);
  }

  // 0 <= x, y, z < kBlockSpan; unallocated leaves read as unobserved, uncoloured ones as black.
  volume::PackedVoxel at(int x, int y, int z) const {
    const volume::PackedVoxel* data = voxels_[x >> 3][y >> 3][z >> 3];
    return data ? data[leafOffset(x & 7, y & 7, z & 7)] : volume::kUnobservedVoxel;
  }
  volume::Rgb8 color(int x, int y, int z) const {
    const volume::PackedColor* data = colors_[x >> 3][y >> 3][z >> 3];
    return data ? volume::unpackColor(data[leafOffset(x & 7, y & 7, z & 7)]) : volume::Rgb8{};
  }
  // The voxels (x, y, 0..7) in a row (`high` false) or (x, y, 8..15) (`high` true), or null where
  // their leaf is not allocated.
  const volume::PackedVoxel* column(int x, int y, bool high) const {
    const volume::PackedVoxel* data = voxels_[x >> 3][y >> 3][high ? 1 : 0];
    return data ? data + leafOffset(x & 7, y & 7, 0) : nullptr;
  }

 private:
  // The buffers of the 2 x 2 x 2 leaves from `origin`, null where a leaf is not allocated.
  template <class Accessor, class Value>
  static void gatherLeaves(const Accessor& grid, const openvdb::Coord& origin, const Value* (&out)[2][2][2]) {
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const auto* leaf = grid.probeConstLeaf(origin.offsetBy(a * kLeafDim, b * kLeafDim, c * kLeafDim));
          out[a][b][c] = leaf ? leaf->buffer().data() : nullptr;
        }
  }

  const volume::PackedVoxel* voxels_[2][2][2] = {};  // [x / 8][y / 8][z / 8]
  const volume::PackedColor* colors_[2][2][2] = {};
};

}  // namespace semfuse::render::detail
