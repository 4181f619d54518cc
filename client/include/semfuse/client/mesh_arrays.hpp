#pragma once
// MeshArrays: the mesh a MapClient fetched (MeshData::ply) as flat per-vertex and per-face arrays,
// for programs that work on the geometry rather than write the file (the Python bindings hand
// them to numpy).
//
//   auto mesh = map.mesh(std::nullopt, timeout);
//   auto arrays = semfuse::client::parseMeshPly(mesh.value().ply);
//   // arrays.value().positions[3 * i + 0..2] is vertex i, arrays.value().labels[i] its label
#include <cstddef>
#include <cstdint>
#include <vector>

#include "semfuse/core/result.hpp"

namespace semfuse::client {

struct MeshArrays {
  std::vector<float> positions;  // x y z per vertex, metres, world frame
  std::vector<float> normals;    // nx ny nz per vertex; empty when the PLY has no normals
  std::vector<uint8_t> colors;   // red green blue per vertex; empty when the PLY has none
  std::vector<uint16_t> labels;  // label per vertex; empty when the PLY has none
  std::vector<float> scores;     // label score per vertex; empty when the PLY has none
  std::vector<uint32_t> faces;   // three vertex indices per triangle

  std::size_t vertexCount() const { return positions.size() / 3; }
  std::size_t faceCount() const { return faces.size() / 3; }
};

// Reads a binary little-endian PLY with a vertex element (x y z required; nx ny nz, red green
// blue, label, score kept when present, other scalar properties skipped) and a face element of
// triangles ("list <uchar|ushort|uint> <int|uint> vertex_indices"): what the server's mesh service
// sends. The PLY comes from the network: counts are checked against the bytes before anything is
// allocated, and a face that indexes past the vertices, a polygon other than a triangle, an ASCII
// or big-endian file or bytes past the end are errors that say where.
Result<MeshArrays> parseMeshPly(const uint8_t* data, std::size_t size);
inline Result<MeshArrays> parseMeshPly(const std::vector<uint8_t>& ply) { return parseMeshPly(ply.data(), ply.size()); }

}  // namespace semfuse::client
