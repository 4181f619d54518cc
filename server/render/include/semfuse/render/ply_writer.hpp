#pragma once
// PLY (binary little endian) of a labeled mesh, for MeshLab, Open3D, Blender and for the mesh
// service, which sends the bytes over DDS. Vertex properties, in order:
//   float x y z; [float nx ny nz]; uchar red green blue; ushort label; float score
// Faces: "list uchar int vertex_indices", triangles only.
#include <cstdint>
#include <string>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/render/mesh.hpp"

namespace semfuse::render {

enum class PlyColor {
  kLabelPalette,  // the legend's colour of each vertex's label (semantic view)
  kVoxelColor,    // the fused camera colour (needs a mesh with colours)
};

struct PlyOptions {
  bool normals = true;
  PlyColor color = PlyColor::kLabelPalette;
};

// Fails when the mesh's per-vertex arrays disagree in length, a triangle indexes past the
// vertices, or voxel colour is asked of a mesh without colours.
Result<std::string> plyBytes(const LabeledMesh& mesh, const LabelLegend& legend, const PlyOptions& options = {});

}  // namespace semfuse::render
