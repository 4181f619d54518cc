#pragma once
// The first pass of CrossingCells::findCrossings(), per leaf in view: read the 9x9 columns of
// 9 voxels that the leaf's cells have as corners (the leaf's own voxels and those of its +x, +y,
// +z neighbours), as bit columns for the crossing masks and as float TSDF for the brick. Two
// implementations with the same results bit for bit: portable, and AVX2 + F16C (8 voxels of a
// column per register, the half floats converted by vcvtph2ps), chosen by setRaycastKernel().
// Internal.
#include <cstdint>

#include "crossing_cells.hpp"

namespace semfuse::render::detail {

struct VoxelColumns {
  static constexpr int kSpan = CrossingCells::kBrickDim;  // 9: voxels 0..8 on each axis
  // Bit z of [x][y]: voxel (x, y, z) is observed / observed with TSDF <= 0 / observed with TSDF > 0.
  uint16_t observed[kSpan][kSpan];
  uint16_t non_positive[kSpan][kSpan];
  uint16_t positive[kSpan][kSpan];
};

// Fills `columns` and the leaf's brick (kBrickStride x + kBrickDim y + z; 0 where a neighbour is
// unallocated, which no crossing cell reads).
void readVoxelColumns(const CrossingCells::LeafCells& leaf, float* brick, VoxelColumns& columns);
// The same with AVX2 + F16C; call only where voxelColumnsAvx2Supported().
void readVoxelColumnsAvx2(const CrossingCells::LeafCells& leaf, float* brick, VoxelColumns& columns);
bool voxelColumnsAvx2Supported();  // built for x86-64 and the CPU has AVX2 and F16C

// Where column (x, y) of a leaf's cells reads its voxels: z = 0..7 at `low` (null when that leaf
// is unallocated), z = 8 at `high[0]` (the +z neighbour; null likewise).
struct ColumnSource {
  const volume::PackedVoxel* low;
  const volume::PackedVoxel* high;
};
inline ColumnSource columnSource(const CrossingCells::LeafCells& leaf, int x, int y) {
  using LeafCells = CrossingCells::LeafCells;
  constexpr int kTop = CrossingCells::kLeafDim;
  const volume::PackedVoxel* low = leaf.upper[LeafCells::upperHolding(x, y, 0)];
  const volume::PackedVoxel* high = leaf.upper[LeafCells::upperHolding(x, y, kTop)];
  return {low ? low + LeafCells::offsetInLeaf(x, y, 0) : nullptr,
          high ? high + LeafCells::offsetInLeaf(x, y, kTop) : nullptr};
}

// Non-positive TSDF read from the half's bits: the sign bit, or a zero magnitude (+0 counts: the
// ray's crossing test is f <= 0). Exactly the halves that are <= 0 as 16-bit signed integers.
inline bool nonPositiveBits(uint64_t bits) { return (bits & 0x8000u) != 0 || (bits & 0x7FFFu) == 0; }

// Voxel `bits` as voxel z of a column: bit z of `seen` where it is observed, of `below` where its
// TSDF bits are <= 0, and its TSDF as float in brick_column[z].
inline void readVoxel(uint64_t bits, int z, float* brick_column, unsigned& seen, unsigned& below) {
  seen |= static_cast<unsigned>((bits & 0xFFFF0000u) != 0) << z;
  below |= static_cast<unsigned>(nonPositiveBits(bits)) << z;
  brick_column[z] = volume::detail::halfValueBranchless(bits);
}

// Both readers, once voxels z = 0..7 of column (x, y) are in: voxel z = 8 (from `source.high`; 0
// and unobserved where that leaf is unallocated), then the column's three bit sets.
inline void finishColumn(const ColumnSource& source, float* brick_column, unsigned seen, unsigned below, int x, int y,
                         VoxelColumns& columns) {
  constexpr int kTop = CrossingCells::kLeafDim;
  if (source.high) {
    readVoxel(static_cast<uint64_t>(source.high[0]), kTop, brick_column, seen, below);
  } else {
    brick_column[kTop] = 0.0f;
  }
  columns.observed[x][y] = static_cast<uint16_t>(seen);
  columns.non_positive[x][y] = static_cast<uint16_t>(seen & below);
  columns.positive[x][y] = static_cast<uint16_t>(seen & ~below);
}

}  // namespace semfuse::render::detail
