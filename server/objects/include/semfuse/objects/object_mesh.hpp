#pragma once
// The labeled mesh of one object: the map's mesh (render::extractMesh, surface nets) inside the
// object's box widened by two voxels, keeping the triangles whose corners lie, at least two of
// three, nearest to a surface voxel of the object (among the 3^3 voxels around each corner).
#include <cstdint>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/core/result.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::objects {

// The id of the surface voxel nearest to `point` (world, metres) among the 3^3 around its nearest
// voxel; 0 where none of them belongs to an object.
int32_t objectIdNear(const openvdb::tree::ValueAccessor<const openvdb::Int32Tree>& ids, const Eigen::Vector3f& point,
                     float voxel_size);

// ids: the object id of every surface voxel (ObjectRegistry::Assignment::id_tree) of the same map.
Result<render::LabeledMesh> objectMesh(const volume::LabeledVolume& map, const openvdb::Int32Tree& ids, uint32_t id,
                                       const Eigen::Vector3d& bbox_min, const Eigen::Vector3d& bbox_max);

}  // namespace semfuse::objects
