#include "mesh_cells.hpp"

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

// Components of the outside corners joined by outside-outside cell edges, then each crossed edge
// labelled with the component of its outside end.
CellTopology buildTopology(uint8_t inside_corners) {
  const auto outside = static_cast<uint8_t>(~inside_corners);
  auto isOutside = [&](int k) { return ((outside >> k) & 1) != 0; };
  int parent[8];
  for (int k = 0; k < 8; ++k) parent[k] = k;
  auto root = [&](int k) {
    while (parent[k] != k) k = parent[k];
    return k;
  };
  for (int k = 0; k < 8; ++k)
    for (int axis = 0; axis < 3; ++axis) {
      const int other = k | (1 << axis);
      if (other != k && isOutside(k) && isOutside(other)) parent[root(other)] = root(k);
    }
  CellTopology topology{};
  int group_of_root[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
  for (int k = 0; k < 8; ++k)
    for (int axis = 0; axis < 3; ++axis) {
      const int other = k | (1 << axis);
      topology.group[k][axis] = -1;
      if (other == k || isOutside(k) == isOutside(other)) continue;
      int& group = group_of_root[root(isOutside(k) ? k : other)];
      if (group < 0) group = topology.groups++;
      topology.group[k][axis] = static_cast<int8_t>(group);
    }
  return topology;
}

// Marks the cells with more than one piece of surface and counts their extra vertices.
void findSplitCells(LeafCells& cells) {
  const std::array<CellTopology, 256>& topologies = cellTopologies();
  uint32_t extra = 0;
  for (int x = 0; x < kLeafDim; ++x)
    for (uint64_t word = cells.surface[x]; word != 0; word &= word - 1) {
      const int bit = __builtin_ctzll(word);
      const uint8_t groups = topologies[cells.insideCorners(x, bit >> 3, bit & 7)].groups;
      if (groups < 2) continue;
      cells.split[x] |= uint64_t{1} << bit;
      cells.split_cells.push_back({static_cast<uint16_t>((x << 6) | bit), extra});
      extra += groups - 1u;
    }
  cells.vertex_count += extra;
}

}  // namespace

const std::array<CellTopology, 256>& cellTopologies() {
  static const std::array<CellTopology, 256> table = [] {
    std::array<CellTopology, 256> t{};
    for (int mask = 0; mask < 256; ++mask) t[mask] = buildTopology(static_cast<uint8_t>(mask));
    return t;
  }();
  return table;
}

uint32_t LeafCells::extraVertex(int x, int y, int z, int group) const {
  const auto id = static_cast<uint16_t>((x << 6) | (y << 3) | z);
  uint32_t first_extra = 0;
  for (const SplitCell& s : split_cells)
    if (s.cell == id) first_extra = s.first_extra;
  return first_vertex + single_count + first_extra + static_cast<uint32_t>(group - 1);
}

uint32_t LeafCells::splitEdgeVertex(int x, int y, int z, int k, int axis) const {
  const int group = cellTopology(insideCorners(x, y, z)).group[k][axis];
  return group == 0 ? vertex(x, y, z) : extraVertex(x, y, z, group);
}

LeafTable::LeafTable(const GeometryTree& tree) {
  leaves_.reserve(tree.leafCount());
  tree.getNodes(leaves_);
  const LeafIndex by_origin(leaves_.size(), [&](std::size_t i) { return leaves_[i]->origin(); });
  neighbours_.resize(leaves_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves_.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i)
                        for (int k = 0; k < 27; ++k)
                          neighbours_[i][k] = by_origin.find(leaves_[i]->origin().offsetBy(
                              (k / 9 - 1) * kLeafDim, ((k / 3) % 3 - 1) * kLeafDim, (k % 3 - 1) * kLeafDim));
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
  if (cell_bounds && !cell_bounds->hasOverlap(openvdb::CoordBBox(origin, origin.offsetBy(kLeafDim - 1)))) return cells;

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
  cells.single_count = cells.vertex_count;
  findSplitCells(cells);
  return cells;
}

}  // namespace semfuse::render::detail
