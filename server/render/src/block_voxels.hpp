#pragma once
// The voxels a mesh block reads: [0, 10)^3 from the block's origin, which is its own leaf and two
// layers of the seven leaves above it (+x, +y, +z and their combinations). At stride 1 they are
// read in place from the map's leaves; at a stride s > 1 the block is one of a coarser lattice,
// its voxel (x, y, z) the map's voxel s * (x, y, z) from the block's origin, copied out of the
// map's leaves. Either can be copied (`BlockVoxelCopy`) to be meshed after the map's lock is
// released. Colour leaves are looked up separately, so that a block found to have no surface
// never probes them. Internal to the block mesher (mesh_blocks.cpp).
#include <algorithm>
#include <array>
#include <memory>

#include <openvdb/openvdb.h>

#include "mesh_cells.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

inline constexpr int kBlockSpan = kLeafDim + 2;  // voxels per side a block reads
inline constexpr int kBlockVoxels = kBlockSpan * kBlockSpan * kBlockSpan;
inline constexpr int kMaxBlockStride = 8;  // the sampled lattice's largest stride

// A block's voxels and colours by themselves, z fastest: what meshing needs without the map.
struct BlockVoxelCopy {
  std::array<volume::PackedVoxel, kBlockVoxels> voxels;
  std::array<volume::PackedColor, kBlockVoxels> colors;
};

class BlockVoxels {
 public:
  // `stride` map voxels per block voxel (1: the map's own lattice).
  explicit BlockVoxels(int stride = 1) : stride_(std::clamp(stride, 1, kMaxBlockStride)) {
    if (stride_ > 1) {
      owned_ = std::make_unique<BlockVoxelCopy>();
      copy_ = owned_.get();
    }
  }
  // Reads a copy made earlier (copyTo); gather() is not called on such a view.
  explicit BlockVoxels(const BlockVoxelCopy& copy) : copy_(&copy) {}

  // The block whose voxel (0, 0, 0) is the map's voxel `origin` (a multiple of 8 * stride).
  // False when none of the map's leaves under the block's own voxels is allocated: then none of
  // its cells is observed.
  bool gather(const volume::GeometryGrid::ConstUnsafeAccessor& geometry, const openvdb::Coord& origin) {
    if (stride_ == 1) {
      gatherLeaves(geometry, origin, voxels_);
      return voxels_[0][0][0] != nullptr;
    }
    return sample(geometry, origin, owned_->voxels);
  }
  void gatherColors(const volume::ColorGrid::ConstUnsafeAccessor& colors, const openvdb::Coord& origin) {
    if (stride_ == 1) gatherLeaves(colors, origin, colors_);
    else sample(colors, origin, owned_->colors);
  }

  // 0 <= x, y, z < kBlockSpan; unallocated leaves read as unobserved, uncoloured ones as black.
  volume::PackedVoxel at(int x, int y, int z) const {
    if (copy_ != nullptr) return copy_->voxels[index(x, y, z)];
    const volume::PackedVoxel* data = voxels_[x >> 3][y >> 3][z >> 3];
    return data ? data[leafOffset(x & 7, y & 7, z & 7)] : volume::kUnobservedVoxel;
  }
  volume::Rgb8 color(int x, int y, int z) const {
    if (copy_ != nullptr) return volume::unpackColor(copy_->colors[index(x, y, z)]);
    const volume::PackedColor* data = colors_[x >> 3][y >> 3][z >> 3];
    return data ? volume::unpackColor(data[leafOffset(x & 7, y & 7, z & 7)]) : volume::Rgb8{};
  }
  // The voxels (x, y, 0..7) in a row (`high` false) or (x, y, 8..9) (`high` true), or null where
  // they are not allocated.
  const volume::PackedVoxel* column(int x, int y, bool high) const {
    if (copy_ != nullptr) return copy_->voxels.data() + index(x, y, high ? kLeafDim : 0);
    const volume::PackedVoxel* data = voxels_[x >> 3][y >> 3][high ? 1 : 0];
    return data ? data + leafOffset(x & 7, y & 7, 0) : nullptr;
  }

  // The voxels (and, when `with_colors`, the colours) gathered, into `out`.
  void copyTo(BlockVoxelCopy& out, bool with_colors) const {
    if (copy_ != nullptr) {
      out.voxels = copy_->voxels;
      if (with_colors) out.colors = copy_->colors;
      return;
    }
    for (int x = 0; x < kBlockSpan; ++x)
      for (int y = 0; y < kBlockSpan; ++y)
        for (int z = 0; z < kBlockSpan; ++z) {
          out.voxels[index(x, y, z)] = at(x, y, z);
          if (with_colors) {
            const volume::PackedColor* data = colors_[x >> 3][y >> 3][z >> 3];
            out.colors[index(x, y, z)] = data ? data[leafOffset(x & 7, y & 7, z & 7)] : 0;
          }
        }
  }

 private:
  static std::size_t index(int x, int y, int z) {
    return static_cast<std::size_t>((x * kBlockSpan + y) * kBlockSpan + z);
  }

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

  // Copies the map's voxels origin + stride * (x, y, z), 0 <= x, y, z < kBlockSpan, into `out`
  // (unallocated ones as Value{}: unobserved, black). Each of the map's leaves under the block is
  // probed once. Whether one under the block's own voxels is allocated.
  template <class Accessor, class Value>
  bool sample(const Accessor& grid, const openvdb::Coord& origin, std::array<Value, kBlockVoxels>& out) const {
    constexpr int kMaxLeaves = (kBlockSpan - 1) * kMaxBlockStride / kLeafDim + 1;  // per axis
    const int leaves = (kBlockSpan - 1) * stride_ / kLeafDim + 1;
    const int own_leaves = (kLeafDim - 1) * stride_ / kLeafDim + 1;
    const Value* leaf[kMaxLeaves][kMaxLeaves][kMaxLeaves] = {};
    bool own = false;
    for (int a = 0; a < leaves; ++a)
      for (int b = 0; b < leaves; ++b)
        for (int c = 0; c < leaves; ++c) {
          const auto* node = grid.probeConstLeaf(origin.offsetBy(a * kLeafDim, b * kLeafDim, c * kLeafDim));
          leaf[a][b][c] = node ? node->buffer().data() : nullptr;
          own = own || (node != nullptr && a < own_leaves && b < own_leaves && c < own_leaves);
        }
    for (int x = 0; x < kBlockSpan; ++x)
      for (int y = 0; y < kBlockSpan; ++y)
        for (int z = 0; z < kBlockSpan; ++z) {
          const int mx = x * stride_, my = y * stride_, mz = z * stride_;
          const Value* data = leaf[mx >> 3][my >> 3][mz >> 3];
          out[index(x, y, z)] = data ? data[leafOffset(mx & 7, my & 7, mz & 7)] : Value{};
        }
    return own;
  }

  int stride_ = 1;
  std::unique_ptr<BlockVoxelCopy> owned_;            // stride > 1: the samples
  const BlockVoxelCopy* copy_ = nullptr;             // set: read from here (samples or a view)
  const volume::PackedVoxel* voxels_[2][2][2] = {};  // stride 1: the leaves, [x / 8][y / 8][z / 8]
  const volume::PackedColor* colors_[2][2][2] = {};
};

}  // namespace semfuse::render::detail
