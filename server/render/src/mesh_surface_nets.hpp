#pragma once
// Surface nets on the labeled TSDF, over the leaves the zero level crosses, parallel over leaves.
// Each crossed cell whose 8 corners were observed (mesh_cells.hpp) gets one vertex per piece of
// surface in it (one, but for cells with faces whose signs alternate), the mean of the points
// where that piece crosses the cell's edges; each crossed voxel edge whose four
// surrounding cells all have a vertex gets a quad, split into two triangles. This is the
// structure OpenVDB's VolumeToMesh builds at adaptivity 0, without its FloatGrid copy of the
// volume, its mask erosion and its tree-wide passes; the vertex attributes come from the corners
// the vertex was placed from, with no second lookup in the tree.
#include <optional>

#include <openvdb/openvdb.h>

#include "semfuse/core/result.hpp"
#include "semfuse/render/mesh.hpp"

namespace semfuse::render::detail {

// cell_bounds: index box of the cells (named by their lowest corner voxel) that may carry surface.
// Fails only when the mesh would need more than 2^32 vertices.
Result<LabeledMesh> surfaceNetsMesh(const volume::LabeledVolume& volume,
                                    const std::optional<openvdb::CoordBBox>& cell_bounds);

}  // namespace semfuse::render::detail
