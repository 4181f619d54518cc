#include "semfuse/objects/object_mesh.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::objects {

int32_t objectIdNear(const openvdb::tree::ValueAccessor<const openvdb::Int32Tree>& ids, const Eigen::Vector3f& p,
                     float voxel_size) {
  const Eigen::Vector3f index = p / voxel_size;
  const openvdb::Coord centre(static_cast<int>(std::floor(index.x() + 0.5f)),
                              static_cast<int>(std::floor(index.y() + 0.5f)),
                              static_cast<int>(std::floor(index.z() + 0.5f)));
  int32_t best = 0;
  float best_distance = std::numeric_limits<float>::infinity();
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const openvdb::Coord c = centre.offsetBy(dx, dy, dz);
        const int32_t id = ids.getValue(c);
        if (id <= 0) continue;
        const float distance = (Eigen::Vector3f(float(c.x()), float(c.y()), float(c.z())) - index).squaredNorm();
        if (distance < best_distance) best_distance = distance, best = id;
      }
  return best;
}

Result<render::LabeledMesh> objectMesh(const volume::LabeledVolume& map, const openvdb::Int32Tree& ids, uint32_t id,
                                       const Eigen::Vector3d& bbox_min, const Eigen::Vector3d& bbox_max) {
  const double margin = 2.0 * map.voxelSize();
  render::MeshOptions options;
  options.bounds =
      render::WorldBounds{bbox_min - Eigen::Vector3d::Constant(margin), bbox_max + Eigen::Vector3d::Constant(margin)};
  auto extracted = render::extractMesh(map, options);
  if (!extracted) return extracted.errorInfo();
  const render::LabeledMesh& mesh = extracted.value();

  // Which vertices lie on the object, in parallel (each thread its own accessor).
  std::vector<uint8_t> on_object(mesh.vertices.size(), 0);
  const float voxel = static_cast<float>(map.voxelSize());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.vertices.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      openvdb::tree::ValueAccessor<const openvdb::Int32Tree> accessor(ids);
                      for (std::size_t v = range.begin(); v != range.end(); ++v)
                        on_object[v] = objectIdNear(accessor, mesh.vertices[v], voxel) == static_cast<int32_t>(id);
                    });

  render::LabeledMesh out;
  std::vector<int64_t> new_index(mesh.vertices.size(), -1);
  auto keep = [&](uint32_t v) {
    if (new_index[v] < 0) {
      new_index[v] = static_cast<int64_t>(out.vertices.size());
      out.vertices.push_back(mesh.vertices[v]);
      out.normals.push_back(mesh.normals[v]);
      out.labels.push_back(mesh.labels[v]);
      out.scores.push_back(mesh.scores[v]);
      if (!mesh.colors.empty()) out.colors.push_back(mesh.colors[v]);
    }
    return static_cast<uint32_t>(new_index[v]);
  };
  for (const auto& triangle : mesh.triangles) {
    if (on_object[triangle[0]] + on_object[triangle[1]] + on_object[triangle[2]] < 2) continue;
    out.triangles.push_back({keep(triangle[0]), keep(triangle[1]), keep(triangle[2])});
  }
  return out;
}

}  // namespace semfuse::objects
