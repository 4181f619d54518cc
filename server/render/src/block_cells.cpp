#include "block_cells.hpp"

#include "mesh_vertex.hpp"

namespace semfuse::render::detail {
namespace {

// Bit z: voxel z of the 8 is observed / observed and inside.
struct ColumnBits {
  unsigned observed = 0, inside = 0;
};

ColumnBits columnBits(const volume::PackedVoxel* voxels, int count) {
  ColumnBits bits;
  if (voxels == nullptr) return bits;
  for (int z = 0; z < count; ++z) {
    const bool observed = volume::isObserved(voxels[z]);
    bits.observed |= static_cast<unsigned>(observed) << z;
    bits.inside |= static_cast<unsigned>(observed && insideBits(voxels[z])) << z;
  }
  return bits;
}

}  // namespace

BlockCells classifyBlockCells(const BlockVoxels& voxels) {
  BlockCells cells;
  std::array<std::array<uint16_t, kBlockSpan>, kBlockSpan> observed{};
  // Column (x, y) reads its 8 voxels in the leaf at the block's height and its top 2 in the
  // leaf above: 64-bit words in a row, no per-voxel choice of leaf.
  for (int x = 0; x < kBlockSpan; ++x)
    for (int y = 0; y < kBlockSpan; ++y) {
      const ColumnBits low = columnBits(voxels.column(x, y, false), kLeafDim);
      const ColumnBits high = columnBits(voxels.column(x, y, true), kBlockSpan - kLeafDim);
      observed[x][y] = static_cast<uint16_t>(low.observed | (high.observed << kLeafDim));
      cells.inside[x][y] = static_cast<uint16_t>(low.inside | (high.inside << kLeafDim));
    }
  constexpr unsigned kAllCells = (1u << kBlockCells) - 1;
  for (int x = 0; x < kBlockCells; ++x)
    for (int y = 0; y < kBlockCells; ++y) {
      unsigned all_observed = 0x3FF, any_inside = 0, all_inside = 0x3FF;
      for (int dx = 0; dx < 2; ++dx)
        for (int dy = 0; dy < 2; ++dy) {
          all_observed &= observed[x + dx][y + dy];
          any_inside |= cells.inside[x + dx][y + dy];
          all_inside &= cells.inside[x + dx][y + dy];
        }
      all_observed &= all_observed >> 1;  // bit z: voxels z and z + 1
      any_inside |= any_inside >> 1;
      all_inside &= all_inside >> 1;
      cells.surface[x][y] = static_cast<uint16_t>(all_observed & any_inside & ~all_inside & kAllCells);
    }
  return cells;
}

}  // namespace semfuse::render::detail
