#include "mesh_cells.hpp"

#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::render::detail {
namespace {

uint16_t observedBit(volume::PackedVoxel v) { return volume::isObserved(v) ? 1 : 0; }

// tsdf < 0 read from the half's bits: sign set and magnitude non-zero (-0 is not inside). The
// vertex pass decides crossings with the same bits, so both passes agree on every edge.
uint16_t insideBit(volume::PackedVoxel v) {
  const auto bits = static_cast<uint64_t>(v);
  return (bits & 0x8000u) != 0 && (bits & 0x7FFFu) != 0 ? 1 : 0;
}

// Clears the cells of the leaf at `origin` that lie outside the bounds.
void clipToBounds(const openvdb::Coord& origin, const openvdb::CoordBBox& bounds, LeafCells& cells) {
  const openvdb::CoordBBox leaf_cells(origin, origin.offsetBy(kLeafDim - 1));
  if (bounds.isInside(leaf_cells)) return;
  if (!bounds.hasOverlap(leaf_cells)) {
    cells.surface.fill(0);
    return;
  }
  for (int x = 0; x < kLeafDim; ++x)
    for (int bit = 0; bit < 64; ++bit)
      if (!bounds.isInside(origin.offsetBy(x, bit >> 3, bit & 7))) cells.surface[x] &= ~(uint64_t{1} << bit);
}

}  // namespace

LeafTable::LeafTable(const GeometryTree& tree) {
  leaves_.reserve(tree.leafCount());
  tree.getNodes(leaves_);
  std::unordered_map<openvdb::Coord, uint32_t> by_origin;
  by_origin.reserve(leaves_.size());
  for (std::size_t i = 0; i < leaves_.size(); ++i) by_origin.emplace(leaves_[i]->origin(), static_cast<uint32_t>(i));
  neighbours_.resize(leaves_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves_.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        for (int k = 0; k < 27; ++k) {
                          const auto it = by_origin.find(leaves_[i]->origin().offsetBy(
                              (k / 9 - 1) * kLeafDim, ((k / 3) % 3 - 1) * kLeafDim, (k % 3 - 1) * kLeafDim));
                          neighbours_[i][k] = it == by_origin.end() ? kNone : it->second;
                        }
                    });
}

VoxelBlock::VoxelBlock(const LeafTable& leaves, std::size_t i) {
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c) {
        const uint32_t n = leaves.neighbour(i, a - 1, b - 1, c - 1);
        data_[a][b][c] = n == LeafTable::kNone ? nullptr : leaves.leaf(n).buffer().data();
      }
}

LeafCells classifyCells(const LeafTable& leaves, std::size_t i, const std::optional<openvdb::CoordBBox>& cell_bounds) {
  constexpr int kBlock = LeafCells::kBlock;
  constexpr int kSpan = kLeafDim + 2;  // voxels -1..8 on each axis
  LeafCells cells;
  const openvdb::Coord origin = leaves.leaf(i).origin();
  if (cell_bounds && !cell_bounds->hasOverlap(openvdb::CoordBBox(origin, origin.offsetBy(kLeafDim - 1))))
    return cells;

  // One 10-bit column per (x, y), -1 <= x, y <= 8: bit z + 1 = voxel (x, y, z) observed / inside.
  const VoxelBlock block(leaves, i);
  std::array<uint16_t, kSpan * kSpan> observed{}, inside{};
  auto span = [](int x, int y) { return kSpan * (x + 1) + (y + 1); };
  for (int x = -1; x <= kLeafDim; ++x)
    for (int y = -1; y <= kLeafDim; ++y) {
      uint16_t seen = 0, in = 0;
      if (const volume::PackedVoxel* column = block.column(x, y))
        for (int z = 0; z < kLeafDim; ++z) {
          seen |= static_cast<uint16_t>(observedBit(column[z]) << (z + 1));
          in |= static_cast<uint16_t>(insideBit(column[z]) << (z + 1));
        }
      for (int z : {-1, kLeafDim}) {
        const volume::PackedVoxel v = block.at(x, y, z);
        seen |= static_cast<uint16_t>(observedBit(v) << (z + 1));
        in |= static_cast<uint16_t>(insideBit(v) << (z + 1));
      }
      observed[span(x, y)] = seen;
      inside[span(x, y)] = static_cast<uint16_t>(in & seen);
      if (x >= 0 && y >= 0) cells.inside[kBlock * x + y] = static_cast<uint16_t>((in & seen) >> 1);
    }

  // Cell (x, y, z) spans columns (x..x+1, y..y+1) and bits z+1..z+2 of them: AND / OR the four
  // columns, then each bit with the one above it.
  for (int x = 0; x < kLeafDim; ++x)
    for (int y = 0; y < kLeafDim; ++y) {
      uint16_t all_observed = 0x3FF, any_inside = 0, all_inside = 0x3FF;
      for (int k : {span(x, y), span(x + 1, y), span(x, y + 1), span(x + 1, y + 1)}) {
        all_observed &= observed[k];
        any_inside |= inside[k];
        all_inside &= inside[k];
      }
      all_observed = static_cast<uint16_t>((all_observed & (all_observed >> 1)) >> 1);  // bit z: z, z+1
      any_inside = static_cast<uint16_t>((any_inside | (any_inside >> 1)) >> 1);
      all_inside = static_cast<uint16_t>((all_inside & (all_inside >> 1)) >> 1);
      const uint64_t crossed = all_observed & any_inside & ~all_inside & 0xFFu;
      cells.surface[x] |= crossed << (kLeafDim * y);
    }
  if (cell_bounds) clipToBounds(origin, *cell_bounds, cells);

  for (int x = 0; x < kLeafDim; ++x) {
    cells.vertices_before_word[x] = cells.vertex_count;
    cells.vertex_count += static_cast<uint32_t>(__builtin_popcountll(cells.surface[x]));
  }
  return cells;
}

}  // namespace semfuse::render::detail
