#pragma once
// Read-only questions about the map that the query services answer, as free functions over a
// LabeledVolume (no DDS): what is at these points, what is in this box, which objects are near.
// The answers are the services' own types (semfuse/core/service_types.hpp).
//
// A "surface voxel" is an observed voxel within half a voxel of the zero crossing
// (|tsdf| < voxel_size / 2): a band one voxel thick, so count * voxel_size^2 estimates area.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/objects/object_tracker.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::server {

// The voxel at each point; an unobserved voxel, or a point that is not finite, gives observed false
// and zeros.
std::vector<VoxelSample> sampleAt(const volume::LabeledVolume& volume, const std::vector<Eigen::Vector3d>& points);

// Observed, occupied (behind the surface, tsdf < 0) and free voxels in the box, and the surface
// voxels per label, by label (0 = unlabeled surface).
RegionSummary summarizeRegion(const volume::LabeledVolume& volume, const Eigen::Vector3d& min,
                              const Eigen::Vector3d& max);

// The objects of a tracked set (server/objects) that a request asks for, as the service answers
// them: of its label (0 = every label), at least min_voxels surface voxels, fragments only when
// asked, and with `near` only those with a surface voxel within radius of the point. Largest first.
std::vector<ObjectInstance> selectObjects(const objects::ObjectSet& set, const ObjectsRequest& request,
                                          double voxel_size);

}  // namespace semfuse::server
