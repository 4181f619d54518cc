#pragma once
// A block's mesh from the render library (floats, in voxels from the block's origin) as the
// live mesh carries it (semfuse/core/map_blocks.hpp): positions in 1/4096 of a voxel, normals
// times 127, colours as bytes, triangle indices as uint16.
#include <cstdint>

#include "semfuse/core/map_blocks.hpp"
#include "semfuse/render/mesh_blocks.hpp"

namespace semfuse::server {

// Takes the mesh by value: a caller done with it moves it in, and its labels and scores move on.
MeshBlock encodeMeshBlock(render::BlockMesh mesh, uint64_t revision);

}  // namespace semfuse::server
