#include "surface_depth_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace semfuse::render::detail {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Camera depth below which a corner counts as "at or behind the camera plane": its projection is
// unbounded, so the box cannot be reduced to a pixel rectangle.
constexpr double kMinProjectableDepth = 1e-6;
// Leaves are judged in blocks of 4^3 cells: smaller blocks give tighter boxes but more of them to
// project and rasterise.
constexpr int kBlockDim = 2;
constexpr int kBlocksPerLeafAxis = CrossingCells::kLeafDim / kBlockDim;
constexpr int kBlocksPerLeaf = kBlocksPerLeafAxis * kBlocksPerLeafAxis * kBlocksPerLeafAxis;
// The boxes are exact; the margins (voxels) only absorb the rounding of the stored float bounds.
constexpr double kNearMarginVoxels = 0.05;
constexpr double kFarMarginVoxels = 0.05;

// Index-space box of the crossing cells in one block: cells lo..hi span [lo, hi + 1].
struct CellBox {
  int lo[3], hi[3];
};

// The tight box of the crossing cells in the 4^3 block at leaf-local (x0, y0, z0); false when
// the block has none. Word x of the mask holds bit 8 y + z.
bool crossingBox(const CrossingCells::LeafCells& leaf, int x0, int y0, int z0, CellBox& box) {
  const uint64_t row = ((uint64_t{1} << kBlockDim) - 1) << z0;  // z0..z0+3 of one y row
  uint64_t square = 0;
  for (int y = y0; y < y0 + kBlockDim; ++y) square |= row << (8 * y);
  uint64_t any = 0;
  int x_lo = -1, x_hi = -1;
  for (int x = x0; x < x0 + kBlockDim; ++x) {
    const uint64_t bits = leaf.crossing[x] & square;
    if (bits == 0) continue;
    if (x_lo < 0) x_lo = x;
    x_hi = x;
    any |= bits;
  }
  if (any == 0) return false;
  const int low_bit = __builtin_ctzll(any), high_bit = 63 - __builtin_clzll(any);
  unsigned z_bits = 0;  // OR of the block's y rows
  for (int y = y0; y < y0 + kBlockDim; ++y) z_bits |= static_cast<unsigned>(any >> (8 * y)) & 0xFFu;
  box.lo[0] = x_lo;
  box.hi[0] = x_hi;
  box.lo[1] = low_bit >> 3;
  box.hi[1] = high_bit >> 3;
  box.lo[2] = __builtin_ctz(z_bits);
  box.hi[2] = 31 - __builtin_clz(z_bits);
  return true;
}

// What the blocks seen by one thread contribute: inclusive rectangles of pixel centres with their
// depth intervals, and the far end of the boxes that reach behind the camera plane (they cannot
// be projected and open every pixel).
struct Footprints {
  std::vector<SurfaceDepthBounds::Rect> rects;
  float behind_camera_far = -kInf;
  std::size_t blocks = 0;  // blocks with a crossing cell, projected or not
};

}  // namespace

SurfaceDepthBounds::SurfaceDepthBounds(const CrossingCells& cells, double voxel, const PinholeIntrinsics& k,
                                       const Pose& camera_to_world, double min_depth, double max_depth)
    : width_(k.width), height_(k.height) {
  const auto& leaves = cells.leaves();
  const double s = voxel;
  const double near_margin = kNearMarginVoxels * s, far_margin = kFarMarginVoxels * s;
  const Eigen::Matrix3d world_to_camera = camera_to_world.linear().transpose();
  const Eigen::Vector3d camera_origin = camera_to_world.translation();
  // Camera-frame unit edges of a box.
  const Eigen::Vector3d ex = world_to_camera.col(0) * s, ey = world_to_camera.col(1) * s,
                        ez = world_to_camera.col(2) * s;

  tbb::enumerable_thread_specific<Footprints> per_thread;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves.size(), 64), [&](const auto& range) {
    Footprints& out = per_thread.local();
    for (std::size_t l = range.begin(); l < range.end(); ++l) {
      const CrossingCells::LeafCells& leaf = leaves[l];
      if (!leaf.anyCrossing()) continue;
      for (int block = 0; block < kBlocksPerLeaf; ++block) {
        const int x0 = (block / (kBlocksPerLeafAxis * kBlocksPerLeafAxis)) * kBlockDim;
        const int y0 = (block / kBlocksPerLeafAxis % kBlocksPerLeafAxis) * kBlockDim;
        const int z0 = (block % kBlocksPerLeafAxis) * kBlockDim;
        CellBox box;
        if (!crossingBox(leaf, x0, y0, z0, box)) continue;
        ++out.blocks;
        const openvdb::Coord o = leaf.origin.offsetBy(box.lo[0], box.lo[1], box.lo[2]);
        const Eigen::Vector3d base = world_to_camera * (Eigen::Vector3d(o.x(), o.y(), o.z()) * s - camera_origin);
        const Eigen::Vector3d edge_x = ex * (box.hi[0] - box.lo[0] + 1), edge_y = ey * (box.hi[1] - box.lo[1] + 1),
                              edge_z = ez * (box.hi[2] - box.lo[2] + 1);
        double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
        double u_min = z_min, u_max = z_max, v_min = z_min, v_max = z_max;
        bool projectable = true;
        for (int c = 0; c < 8; ++c) {
          Eigen::Vector3d p = base;
          if (c & 1) p += edge_x;
          if (c & 2) p += edge_y;
          if (c & 4) p += edge_z;
          z_min = std::min(z_min, p.z());
          z_max = std::max(z_max, p.z());
          if (p.z() < kMinProjectableDepth) {
            projectable = false;
            continue;
          }
          const double inv_z = 1.0 / p.z();
          const double u = k.fx * p.x() * inv_z + k.cx, v = k.fy * p.y() * inv_z + k.cy;
          u_min = std::min(u_min, u);
          u_max = std::max(u_max, u);
          v_min = std::min(v_min, v);
          v_max = std::max(v_max, v);
        }
        if (z_max < min_depth || z_min > max_depth) continue;  // outside the depth range entirely
        const auto far = static_cast<float>(std::min(z_max, max_depth) + far_margin);
        if (!projectable) {
          out.behind_camera_far = std::max(out.behind_camera_far, far);
          continue;
        }
        // Pixel centres (integers) inside [u_min, u_max] x [v_min, v_max], clipped to the image.
        const double u0 = std::max(std::ceil(u_min), 0.0), u1 = std::min(std::floor(u_max), k.width - 1.0);
        const double v0 = std::max(std::ceil(v_min), 0.0), v1 = std::min(std::floor(v_max), k.height - 1.0);
        if (u0 > u1 || v0 > v1) continue;
        out.rects.push_back({static_cast<int>(u0), static_cast<int>(u1), static_cast<int>(v0), static_cast<int>(v1),
                             static_cast<float>(std::max(z_min, min_depth) - near_margin), far});
      }
    }
  });

  // A box behind the camera plane opens every pixel from the near clip to its far depth. The
  // others are filed under every band of rows their rectangle touches (a counting sort).
  open_far_ = -kInf;
  band_start_.assign(static_cast<std::size_t>(bandCount()) + 1, 0);
  for (const Footprints& f : per_thread) {
    surface_blocks_ += f.blocks;
    open_far_ = std::max(open_far_, f.behind_camera_far);
    for (const Rect& r : f.rects)
      for (int band = r.v0 / kBandRows; band <= r.v1 / kBandRows; ++band) ++band_start_[band + 1];
  }
  open_near_ = open_far_ > -kInf ? static_cast<float>(min_depth - near_margin) : kInf;
  for (std::size_t band = 0; band + 1 < band_start_.size(); ++band) band_start_[band + 1] += band_start_[band];
  footprints_.resize(band_start_.back());
  std::vector<std::size_t> next(band_start_.begin(), band_start_.end() - 1);
  for (const Footprints& f : per_thread)
    for (const Rect& r : f.rects)
      for (int band = r.v0 / kBandRows; band <= r.v1 / kBandRows; ++band) footprints_[next[band]++] = r;
}

void SurfaceDepthBounds::rasterizeBand(int band, BandBounds& out) const {
  out.v_begin_ = band * kBandRows;
  out.width_ = width_;
  const int rows = std::min(kBandRows, height_ - out.v_begin_);
  const std::size_t pixels = static_cast<std::size_t>(rows) * width_;
  out.near_.assign(pixels, open_near_);
  out.far_.assign(pixels, open_far_);
  for (std::size_t i = band_start_[band]; i < band_start_[band + 1]; ++i) {
    const Rect& f = footprints_[i];
    const int v0 = std::max(f.v0, out.v_begin_), v1 = std::min(f.v1, out.v_begin_ + rows - 1);
    for (int v = v0; v <= v1; ++v) {
      float* near_row = out.near_.data() + static_cast<std::size_t>(v - out.v_begin_) * width_;
      float* far_row = out.far_.data() + static_cast<std::size_t>(v - out.v_begin_) * width_;
      for (int u = f.u0; u <= f.u1; ++u) {
        near_row[u] = std::min(near_row[u], f.near);
        far_row[u] = std::max(far_row[u], f.far);
      }
    }
  }
}

}  // namespace semfuse::render::detail
