#pragma once
// Voxels of the field addressed by leaf and offset, and the 3 x 3 x 3 block of leaves around one:
// the waves read up to 26 neighbours of every voxel they take, and a neighbour inside the same leaf
// (three in four of them) is then an array index instead of a walk down the tree.
#include <array>
#include <cstdint>

#include "semfuse/esdf/esdf_voxel.hpp"

namespace semfuse::esdf::detail {

using FieldTree = EsdfGrid::TreeType;
using FieldLeaf = FieldTree::LeafNodeType;
inline constexpr int kLeafDim = FieldLeaf::DIM;

// OpenVDB's leaf offset n = x * 64 + y * 8 + z (local coordinates).
inline int leafOffset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }
inline openvdb::Coord localCoord(int n) { return {n >> 6, (n >> 3) & 7, n & 7}; }

struct VoxelRef {
  FieldLeaf* leaf = nullptr;
  uint32_t n = 0;

  openvdb::Coord coord() const { return leaf->origin() + localCoord(static_cast<int>(n)); }
  PackedEsdf packed() const { return leaf->getValue(n); }
  EsdfVoxel voxel() const { return unpackEsdf(packed()); }
  bool known() const { return leaf->valueMask().isOn(n); }
  // Keeps the voxel's known / unknown state.
  void write(const EsdfVoxel& v) const { leaf->setValueOnly(n, packEsdf(v)); }
};

// The leaves around a centre leaf, looked up in the tree the first time each is asked for.
class LeafNeighbourhood {
 public:
  explicit LeafNeighbourhood(FieldTree& tree) : leaves_(tree) {}

  // Forgets every leaf looked up: leaves may have come and gone since.
  void reset() {
    leaves_.clear();
    centre_ = nullptr;
    resolved_ = 0;
  }

  // The voxel one step (each of dx, dy, dz in -1..1) from `from`; false outside the field's leaves.
  bool step(const VoxelRef& from, int dx, int dy, int dz, VoxelRef& to) {
    const int x = static_cast<int>(from.n >> 6) + dx, y = static_cast<int>((from.n >> 3) & 7) + dy,
              z = static_cast<int>(from.n & 7) + dz;
    // -1 -> leaf -1, 0..7 -> 0, 8 -> +1 (arithmetic shift), local coordinate wraps with & 7.
    const int block = ((x >> 3) + 1) * 9 + ((y >> 3) + 1) * 3 + ((z >> 3) + 1);
    FieldLeaf* leaf = block == kCentre ? from.leaf : around(from.leaf, block);
    if (!leaf) return false;
    to = {leaf, static_cast<uint32_t>(leafOffset(x & 7, y & 7, z & 7))};
    return true;
  }

 private:
  static constexpr int kCentre = 13;

  FieldLeaf* around(FieldLeaf* centre, int block) {
    if (centre != centre_) {
      centre_ = centre;
      resolved_ = 0;
    }
    const uint32_t bit = uint32_t{1} << block;
    if (!(resolved_ & bit)) {
      const openvdb::Coord shift((block / 9 - 1) * kLeafDim, (block / 3 % 3 - 1) * kLeafDim,
                                 (block % 3 - 1) * kLeafDim);
      around_[block] = leaves_.probeLeaf(centre->origin() + shift);
      resolved_ |= bit;
    }
    return around_[block];
  }

  openvdb::tree::ValueAccessor<FieldTree> leaves_;
  const FieldLeaf* centre_ = nullptr;
  uint32_t resolved_ = 0;  // bit per block: around_ holds its leaf (or null: none there)
  std::array<FieldLeaf*, 27> around_{};
};

}  // namespace semfuse::esdf::detail
