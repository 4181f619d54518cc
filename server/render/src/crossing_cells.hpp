#pragma once
// Which voxel cells a ray can find the surface in, leaf by leaf, for raycast(). Internal.
//
// A ray reports the surface where the trilinear TSDF turns from positive to non-positive inside
// one cell (the 2x2x2 voxels from a base voxel). Trilinear values are convex combinations of the
// cell's 8 corners, so that needs all 8 corners observed, one of them > 0 and one <= 0: a
// "crossing cell". Every other cell can be stepped over without reading a voxel. Per leaf that is
// a 512-bit mask, built once per raycast from the voxels with bit operations, and only for the
// leaves that meet the view frustum (no ray enters the others).
//
// The leaves are found by origin through a LeafIndex (a ray moves from leaf to leaf every few
// cells), which also gives the voxels of the +x/+y/+z neighbours that the cells on a leaf's upper
// faces read.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <openvdb/openvdb.h>

#include "leaf_index.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

// Index-space box (voxel units; voxel (i, j, k) at (i, j, k)) and half-space that both hold
// every point of the crossing cells of one 2^3 block of cells where the trilinear TSDF is <= 0:
// a ray's crossing in that block lies inside both.
struct SurfaceBox {
  float lo[3], hi[3];
  float normal[3];  // the half-space normal . p <= offset (normal: about the TSDF gradient,
  float offset;     // metres of TSDF per voxel)
};

class CrossingCells {
 public:
  using Leaf = volume::GeometryGrid::TreeType::LeafNodeType;
  static constexpr int kLeafDim = Leaf::DIM;  // 8
  static_assert(kLeafDim == 8, "the crossing masks hold one 64-bit word per x slice of an 8^3 leaf");
  static constexpr int kBrickDim = kLeafDim + 1;  // voxels per axis that the cells of a leaf read
  static constexpr int kBrickStride = kBrickDim * kBrickDim;
  static constexpr int kBrickSize = kBrickDim * kBrickStride;

  struct LeafCells {
    openvdb::Coord origin;
    const volume::PackedVoxel* voxels = nullptr;  // z fastest: offset = 64 x + 8 y + z
    const volume::PackedColor* colors = nullptr;  // same layout; only when colour was asked for
    bool in_view = false;                         // meets the frustum
    // Voxels (and colours) of this leaf and of its upper neighbours, index dx + 2 dy + 4 dz (0 =
    // this leaf): the corners of the cells on the upper faces lie there. Null where unallocated;
    // filled for the leaves in view only.
    const volume::PackedVoxel* upper[8] = {};
    const volume::PackedColor* upper_colors[8] = {};
    // Word x, bit 8 y + z: cell (x, y, z) (leaf-local base voxel) is a crossing cell. All zero
    // until findCrossings(), and for leaves outside the frustum given to the constructor.
    std::array<uint64_t, kLeafDim> crossing{};
    // The TSDF (metres, as float) of voxels (x, y, z), 0 <= x, y, z <= 8, of this leaf and its
    // upper neighbours, at kBrickStride * x + kBrickDim * y + z: a crossing cell's 8 corners
    // at fixed offsets, with no branch for the cells on upper faces and no half conversion per
    // ray. Filled by findCrossings() for the leaves in view; null for the others.
    const float* tsdf = nullptr;
    // The same, coarser, so that a ray steps over empty blocks at once: bit 16 bx + 4 by + bz is
    // the 2^3 block of cells (2 bx.., 2 by.., 2 bz..), bit 4 bx + 2 by + bz the 4^3 block.
    uint64_t blocks2 = 0;
    uint8_t blocks4 = 0;

    // Voxel (x, y, z), 0 <= x, y, z <= 8 leaf-local (8 lies in an upper neighbour), is voxel
    // offsetInLeaf(x, y, z) of upper[upperHolding(x, y, z)] (and of upper_colors[...]).
    static int upperHolding(int x, int y, int z) { return (x >> 3) | ((y >> 3) << 1) | ((z >> 3) << 2); }
    static int offsetInLeaf(int x, int y, int z) { return ((x & 7) << 6) | ((y & 7) << 3) | (z & 7); }

    bool isCrossing(int x, int y, int z) const { return (crossing[x] >> ((y << 3) | z)) & 1u; }
    // Edge (8, 4 or 2 cells) of the largest aligned block around local cell (x, y, z) that holds
    // no crossing cell, or 1 when the 2^3 block around it holds one.
    int emptyBlockDim(int x, int y, int z) const {
      if (blocks2 == 0) return 8;
      if (!((blocks4 >> (((x >> 2) << 2) | ((y >> 2) << 1) | (z >> 2))) & 1u)) return 4;
      if (!((blocks2 >> (((x >> 1) << 4) | ((y >> 1) << 2) | (z >> 1))) & 1u)) return 2;
      return 1;
    }
  };

  struct Options {
    // Copy the voxels the rays can read (leaves in view and their upper neighbours) instead of
    // pointing into the volume: the copy stays valid while the volume changes (the server
    // copies under its lock, a few ms, and renders without it).
    bool copy_voxels = false;
    bool with_color = false;  // also index (or copy) the colour of those leaves
  };

  // Indexes every leaf of `volume` and finds those that meet the frustum of a `k` camera at
  // `camera_to_world` between min_depth and max_depth. Parallel (TBB).
  CrossingCells(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& camera_to_world,
                double min_depth, double max_depth, Options options);
  // Computes the crossing masks, TSDF bricks and surface boxes of the leaves in view
  // (parallel); reads only their voxels (or the copies), not the volume.
  void findCrossings();
  static constexpr int kSurfaceBlockDim = 2;  // cells per axis of the blocks with a SurfaceBox
  // One box per 2^3 block of cells, of the leaves in view, that holds a crossing cell (in no
  // particular order). Empty until findCrossings().
  const std::vector<SurfaceBox>& surfaceBoxes() const { return surface_boxes_; }

  // The leaf whose origin is `origin` (a multiple of 8 on each axis), or null where unallocated.
  const LeafCells* find(const openvdb::Coord& origin) const {
    const uint32_t index = index_.find(origin);
    return index == LeafIndex::kNone ? nullptr : &leaves_[index];
  }
  const std::vector<LeafCells>& leaves() const { return leaves_; }

 private:
  std::vector<LeafCells> leaves_;
  std::unique_ptr<volume::PackedVoxel[]> voxel_copies_;  // copy_voxels: Leaf::SIZE voxels per needed leaf
  std::unique_ptr<volume::PackedColor[]> color_copies_;
  // kBrickSize per leaf in view, in leaf order; uninitialised until findCrossings() writes them
  // (a std::vector would zero ~12 MB per raycast first).
  std::unique_ptr<float[]> bricks_;
  std::vector<SurfaceBox> surface_boxes_;
  LeafIndex index_;  // origin -> position in leaves_
};

}  // namespace semfuse::render::detail
