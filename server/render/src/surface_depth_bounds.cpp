#include "surface_depth_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::render::detail {
namespace {

using GeometryLeaf = volume::GeometryGrid::TreeType::LeafNodeType;
constexpr float kInf = std::numeric_limits<float>::infinity();

// Camera depth below which a corner counts as "at or behind the camera plane": its projection is
// unbounded, so the box cannot be reduced to a pixel rectangle.
constexpr double kMinProjectableDepth = 1e-6;
// Leaves are judged in blocks of 4^3 voxels: a leaf's box spans up to 15 voxels of camera depth
// when seen obliquely, and a ray starts at the nearest depth of the boxes over its pixel, so
// smaller boxes start rays closer to their surface (at the price of more boxes to project).
constexpr int kBlockDim = 4;
constexpr int kBlocksPerLeafAxis = GeometryLeaf::DIM / kBlockDim;
constexpr int kBlocksPerLeaf = kBlocksPerLeafAxis * kBlocksPerLeafAxis * kBlocksPerLeafAxis;
// Index-space box of a surface block: one voxel below its origin (a cell based there reads the
// block's voxels) to the far corner of its last cell.
constexpr int kBoxLow = -1;
constexpr int kBoxEdge = kBlockDim + 1;
// A ray starts this far (voxels) in front of the nearest box, so that the positive sample that
// brackets a crossing just inside the box is taken too; the far end only needs to survive float
// rounding of the stored bound.
constexpr double kNearMarginVoxels = 1.0;
constexpr double kFarMarginVoxels = 0.5;

// True when some observed voxel of the leaf's block at (x0, y0, z0) (leaf-local) has TSDF <= 0:
// the half's sign bit, or a zero magnitude. Unobserved voxels are all-zero bits, so "observed"
// (weight bits) is tested as well.
bool holdsNonPositiveVoxel(const volume::PackedVoxel* leaf_values, int x0, int y0, int z0) {
  bool found = false;
  for (int x = x0; x < x0 + kBlockDim; ++x)
    for (int y = y0; y < y0 + kBlockDim; ++y) {
      // OpenVDB leaves store z fastest: offset = x * 64 + y * 8 + z.
      const volume::PackedVoxel* row = leaf_values + x * 64 + y * 8 + z0;
      for (int z = 0; z < kBlockDim; ++z) {
        const auto bits = static_cast<uint64_t>(row[z]);
        found |= (bits & 0xFFFF0000u) != 0 && ((bits & 0x8000u) != 0 || (bits & 0x7FFFu) == 0);
      }
    }
  return found;
}

// What one surface block contributes: an inclusive rectangle of pixel centres with its depth
// interval, or (behind_camera) a box that cannot be projected and opens every pixel.
struct Footprint {
  int u0 = 0, u1 = -1, v0 = 0, v1 = -1;  // empty unless u0 <= u1 and v0 <= v1
  float near = kInf, far = -kInf;
  bool behind_camera = false;
  bool surface = false;  // the block holds a non-positive voxel at all
};

}  // namespace

SurfaceDepthBounds::SurfaceDepthBounds(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                                       const Pose& camera_to_world, double min_depth, double max_depth)
    : width_(k.width), height_(k.height) {
  std::vector<const GeometryLeaf*> leaves;
  leaves.reserve(volume.geometryGrid().tree().leafCount());
  volume.geometryGrid().tree().getNodes(leaves);

  const double s = volume.voxelSize();
  const double near_margin = kNearMarginVoxels * s, far_margin = kFarMarginVoxels * s;
  const Eigen::Matrix3d world_to_camera = camera_to_world.linear().transpose();
  const Eigen::Vector3d camera_origin = camera_to_world.translation();
  // Camera-frame edges of a box.
  const double edge = kBoxEdge * s;
  const Eigen::Vector3d ex = world_to_camera.col(0) * edge, ey = world_to_camera.col(1) * edge,
                        ez = world_to_camera.col(2) * edge;

  std::vector<Footprint> blocks(leaves.size() * kBlocksPerLeaf);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), 256), [&](const auto& range) {
    for (std::size_t b = range.begin(); b < range.end(); ++b) {
      const GeometryLeaf& leaf = *leaves[b / kBlocksPerLeaf];
      const int block = static_cast<int>(b % kBlocksPerLeaf);
      const int x0 = (block / (kBlocksPerLeafAxis * kBlocksPerLeafAxis)) * kBlockDim;
      const int y0 = (block / kBlocksPerLeafAxis % kBlocksPerLeafAxis) * kBlockDim;
      const int z0 = (block % kBlocksPerLeafAxis) * kBlockDim;
      if (leaf.isEmpty() || !holdsNonPositiveVoxel(leaf.buffer().data(), x0, y0, z0)) continue;
      Footprint& f = blocks[b];
      f.surface = true;
      const openvdb::Coord o = leaf.origin().offsetBy(x0 + kBoxLow, y0 + kBoxLow, z0 + kBoxLow);
      const Eigen::Vector3d base = world_to_camera * (Eigen::Vector3d(o.x(), o.y(), o.z()) * s - camera_origin);
      double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
      double u_min = z_min, u_max = z_max, v_min = z_min, v_max = z_max;
      bool projectable = true;
      for (int c = 0; c < 8; ++c) {
        Eigen::Vector3d p = base;
        if (c & 1) p += ex;
        if (c & 2) p += ey;
        if (c & 4) p += ez;
        z_min = std::min(z_min, p.z());
        z_max = std::max(z_max, p.z());
        if (p.z() < kMinProjectableDepth) {
          projectable = false;
          continue;
        }
        const double u = k.fx * p.x() / p.z() + k.cx, v = k.fy * p.y() / p.z() + k.cy;
        u_min = std::min(u_min, u);
        u_max = std::max(u_max, u);
        v_min = std::min(v_min, v);
        v_max = std::max(v_max, v);
      }
      if (z_max < min_depth || z_min > max_depth) continue;  // outside the depth range entirely
      f.far = static_cast<float>(std::min(z_max, max_depth) + far_margin);
      if (!projectable) {
        f.behind_camera = true;
        continue;
      }
      // Pixel centres (integers) inside [u_min, u_max] x [v_min, v_max], clipped to the image.
      const double u0 = std::max(std::ceil(u_min), 0.0), u1 = std::min(std::floor(u_max), k.width - 1.0);
      const double v0 = std::max(std::ceil(v_min), 0.0), v1 = std::min(std::floor(v_max), k.height - 1.0);
      if (u0 > u1 || v0 > v1) continue;
      f.u0 = static_cast<int>(u0);
      f.u1 = static_cast<int>(u1);
      f.v0 = static_cast<int>(v0);
      f.v1 = static_cast<int>(v1);
      f.near = static_cast<float>(std::max(z_min, min_depth) - near_margin);
    }
  });

  // A box behind the camera plane opens every pixel from the near clip to its far depth. The
  // others are filed under every band of rows their rectangle touches.
  open_far_ = -kInf;
  std::vector<std::vector<std::size_t>> per_band(static_cast<std::size_t>(bandCount()));
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const Footprint& f = blocks[b];
    surface_blocks_ += f.surface ? 1 : 0;
    if (f.behind_camera) open_far_ = std::max(open_far_, f.far);
    if (f.u0 > f.u1 || f.v0 > f.v1) continue;
    for (int band = f.v0 / kBandRows; band <= f.v1 / kBandRows; ++band) per_band[band].push_back(b);
  }
  open_near_ = open_far_ > -kInf ? static_cast<float>(min_depth - near_margin) : kInf;
  band_start_.assign(per_band.size() + 1, 0);
  for (std::size_t band = 0; band < per_band.size(); ++band)
    band_start_[band + 1] = band_start_[band] + per_band[band].size();
  footprints_.reserve(band_start_.back());
  for (const auto& band : per_band)
    for (std::size_t b : band) {
      const Footprint& f = blocks[b];
      footprints_.push_back({f.u0, f.u1, f.v0, f.v1, f.near, f.far});
    }
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
