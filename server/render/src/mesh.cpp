#include "semfuse/render/mesh.hpp"

#include <algorithm>
#include <cmath>

#include "mesh_surface_nets.hpp"
#include "mesh_volume_to_mesh.hpp"

namespace semfuse::render {
namespace {

// The cells whose lowest corner voxel lies inside the world box.
openvdb::CoordBBox cellBounds(const WorldBounds& bounds, double voxel_size) {
  const Eigen::Vector3d lo = (bounds.min / voxel_size).array().ceil();
  const Eigen::Vector3d hi = (bounds.max / voxel_size).array().floor();
  auto clampInt = [](double v) { return static_cast<int>(std::clamp(v, -1e9, 1e9)); };
  return {openvdb::Coord(clampInt(lo.x()), clampInt(lo.y()), clampInt(lo.z())),
          openvdb::Coord(clampInt(hi.x()), clampInt(hi.y()), clampInt(hi.z()))};
}

}  // namespace

Result<LabeledMesh> extractMesh(const volume::LabeledVolume& volume, const MeshOptions& options) {
  std::optional<openvdb::CoordBBox> cell_bounds;
  if (options.bounds) {
    const WorldBounds& b = *options.bounds;
    if (!b.min.allFinite() || !b.max.allFinite() || (b.max - b.min).minCoeff() <= 0.0)
      return makeError("mesh bounding box must be finite with max > min on every axis");
    cell_bounds = cellBounds(b, volume.voxelSize());
  }
  if (options.method == MeshMethod::kSurfaceNets) return detail::surfaceNetsMesh(volume, cell_bounds);
  return detail::volumeToMeshReference(volume, cell_bounds);
}

}  // namespace semfuse::render
