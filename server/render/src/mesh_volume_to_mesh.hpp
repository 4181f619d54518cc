#pragma once
// The reference mesher (MeshMethod::kOpenVdbVolumeToMesh): openvdb::tools::VolumeToMesh on a
// FloatGrid copy of the TSDF, masked by the observed voxels eroded once. Tests and the benchmark
// compare the default surface nets of mesh_surface_nets.hpp with it.
#include <optional>

#include <openvdb/openvdb.h>

#include "semfuse/render/mesh.hpp"

namespace semfuse::render::detail {

// cell_bounds: index box of the cells (named by their lowest corner voxel) that may carry surface.
LabeledMesh volumeToMeshReference(const volume::LabeledVolume& volume,
                                  const std::optional<openvdb::CoordBBox>& cell_bounds);

}  // namespace semfuse::render::detail
