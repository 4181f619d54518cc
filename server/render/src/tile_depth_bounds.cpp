#include "tile_depth_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace semfuse::render::detail {
namespace {

using GeometryLeaf = volume::GeometryGrid::TreeType::LeafNodeType;

// Camera depth below which a corner counts as "at or behind the camera plane": its projection is
// unbounded, so the leaf cannot be reduced to a pixel rectangle.
constexpr double kMinProjectableDepth = 1e-6;

}  // namespace

TileDepthBounds::TileDepthBounds(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                                 const Pose& camera_to_world, double min_depth, double max_depth) {
  tiles_x_ = (k.width + kTileSize - 1) / kTileSize;
  tiles_y_ = (k.height + kTileSize - 1) / kTileSize;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  tiles_.assign(static_cast<std::size_t>(tiles_x_) * tiles_y_, Range{kInf, -kInf});

  const double s = volume.voxelSize();
  // float rounding of the stored bounds must never cut a ray short: widen them by half a voxel.
  const double margin = 0.5 * s;
  const Eigen::Matrix3d world_to_camera = camera_to_world.linear().transpose();
  const Eigen::Vector3d camera_origin = camera_to_world.translation();
  // Camera-frame edges of a leaf box (8 voxels along each index axis).
  const double edge = GeometryLeaf::DIM * s;
  const Eigen::Vector3d ex = world_to_camera.col(0) * edge, ey = world_to_camera.col(1) * edge,
                        ez = world_to_camera.col(2) * edge;
  bool open_everything = false;
  float open_far = -kInf;

  for (auto leaf = volume.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf) {
    if (leaf->isEmpty()) continue;  // no observed voxel: no valid sample starts here
    const openvdb::Coord o = leaf->origin();
    const Eigen::Vector3d base = world_to_camera * (Eigen::Vector3d(o.x(), o.y(), o.z()) * s - camera_origin);
    double z_min = std::numeric_limits<double>::infinity(), z_max = -z_min;
    double u_min = z_min, u_max = z_max, v_min = z_min, v_max = z_max;
    bool projectable = true;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d p = base + ((c & 1) ? ex : Eigen::Vector3d::Zero()) +
                                ((c & 2) ? ey : Eigen::Vector3d::Zero()) + ((c & 4) ? ez : Eigen::Vector3d::Zero());
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
    const auto far = static_cast<float>(std::min(z_max, max_depth) + margin);
    if (!projectable) {
      open_everything = true;
      open_far = std::max(open_far, far);
      continue;
    }
    // Pixel centres (integers) inside [u_min, u_max] x [v_min, v_max], clipped to the image.
    const double u0 = std::max(std::ceil(u_min), 0.0), u1 = std::min(std::floor(u_max), k.width - 1.0);
    const double v0 = std::max(std::ceil(v_min), 0.0), v1 = std::min(std::floor(v_max), k.height - 1.0);
    if (u0 > u1 || v0 > v1) continue;
    const auto near = static_cast<float>(std::max(z_min, min_depth) - margin);
    const int tx0 = static_cast<int>(u0) / kTileSize, tx1 = static_cast<int>(u1) / kTileSize;
    const int ty0 = static_cast<int>(v0) / kTileSize, ty1 = static_cast<int>(v1) / kTileSize;
    for (int ty = ty0; ty <= ty1; ++ty)
      for (int tx = tx0; tx <= tx1; ++tx) {
        Range& r = tiles_[static_cast<std::size_t>(ty) * tiles_x_ + tx];
        r.near = std::min(r.near, near);
        r.far = std::max(r.far, far);
      }
  }
  if (open_everything) {
    const auto near = static_cast<float>(min_depth - margin);
    for (Range& r : tiles_) {
      r.near = std::min(r.near, near);
      r.far = std::max(r.far, open_far);
    }
  }
}

}  // namespace semfuse::render::detail
