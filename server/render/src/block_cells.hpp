#pragma once
// Which cells of a mesh block carry a surface nets vertex, as bit columns: the block mesher's
// first pass, and the test that lets a block without surface of its own (most of the blocks a
// live update re-meshes) cost one read of its voxels and nothing more.
//
// Cell (x, y, z) is named by its lowest corner voxel; it carries a vertex when its 8 corners
// are all observed and some, not all, lie inside (as in mesh_cells.hpp). The block's own cells
// are [0, 8)^3; the layer of cells above them (x, y or z = 8) lends the vertices of quads that
// reach into the blocks above. Internal to the block mesher (mesh_blocks.cpp).
#include <array>
#include <cstdint>

#include "block_voxels.hpp"

namespace semfuse::render::detail {

inline constexpr int kBlockCells = kLeafDim + 1;  // cells per side whose vertices a block may use

struct BlockCells {
  // Bit z of [x][y]: voxel (x, y, z), 0 <= x, y, z < kBlockSpan, is observed and inside.
  std::array<std::array<uint16_t, kBlockSpan>, kBlockSpan> inside{};
  // Bit z of [x][y]: cell (x, y, z), 0 <= x, y, z < kBlockCells, carries a vertex.
  std::array<std::array<uint16_t, kBlockCells>, kBlockCells> surface{};

  bool isSurface(int x, int y, int z) const { return ((surface[x][y] >> z) & 1u) != 0; }
  bool isInside(int x, int y, int z) const { return ((inside[x][y] >> z) & 1u) != 0; }
  // Bit k: corner k = dx + 2 dy + 4 dz of cell (x, y, z) is inside.
  uint8_t insideCorners(int x, int y, int z) const {
    unsigned mask = 0;
    for (int dx = 0; dx < 2; ++dx)
      for (int dy = 0; dy < 2; ++dy) {
        const unsigned pair = (inside[x + dx][y + dy] >> z) & 3u;  // corners at z and z + 1
        mask |= ((pair & 1u) | ((pair & 2u) << 3)) << (dx + 2 * dy);
      }
    return static_cast<uint8_t>(mask);
  }
  // Whether one of the block's own cells carries a vertex. Without one the block has no
  // triangles (each quad has an own cell among its four) and so no vertices either.
  bool hasOwnSurface() const {
    unsigned any = 0;
    for (int x = 0; x < kLeafDim; ++x)
      for (int y = 0; y < kLeafDim; ++y) any |= surface[x][y];
    return (any & 0xFFu) != 0;
  }
};

BlockCells classifyBlockCells(const BlockVoxels& voxels);

}  // namespace semfuse::render::detail
