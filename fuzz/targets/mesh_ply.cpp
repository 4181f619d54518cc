// Fuzz target: the bytes of a mesh PLY as the mesh service sends them -> client::parseMeshPly
// (client/src/mesh_arrays.cpp, compiled into the target), which the Python package and any client
// that wants arrays read a fetched mesh with. What it accepts is consistent: three coordinates per
// vertex, every other per-vertex array empty or one (or three) per vertex, every face index below
// the vertex count.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "semfuse/client/mesh_arrays.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto mesh = semfuse::client::parseMeshPly(data, size);
  if (!mesh) return 0;
  const semfuse::client::MeshArrays& m = mesh.value();
  const size_t n = m.vertexCount();
  SEMFUSE_FUZZ_CHECK(m.positions.size() == 3 * n);
  SEMFUSE_FUZZ_CHECK(m.normals.empty() || m.normals.size() == 3 * n);
  SEMFUSE_FUZZ_CHECK(m.colors.empty() || m.colors.size() == 3 * n);
  SEMFUSE_FUZZ_CHECK(m.labels.empty() || m.labels.size() == n);
  SEMFUSE_FUZZ_CHECK(m.scores.empty() || m.scores.size() == n);
  SEMFUSE_FUZZ_CHECK(m.faces.size() % 3 == 0);
  for (uint32_t index : m.faces) SEMFUSE_FUZZ_CHECK(index < n);
  return 0;
}
