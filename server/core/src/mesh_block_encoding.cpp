#include "mesh_block_encoding.hpp"

#include <algorithm>
#include <cmath>

namespace semfuse::server {
namespace {

// std::lround of a float in [0, 65535] without the library call (six per vertex add up over
// thousands of blocks a round): x + 0.5 in double keeps every bit of x that could change the
// floor, and truncating a non-negative value floors it, so halves round up as lround's do.
long roundNonNegative(float x) { return static_cast<long>(static_cast<double>(x) + 0.5); }

uint16_t positionUnits(float voxels) {
  // A block's vertices lie in [0, 9] voxels from its origin, 36864 units at most.
  const float units = voxels * MeshBlock::kPositionScale;
  if (!(units > 0.0F)) return 0;
  return static_cast<uint16_t>(units >= 65535.0F ? 65535L : roundNonNegative(units));
}

int8_t normalUnits(float component) {
  if (!std::isfinite(component)) return 0;
  const float units = component * 127.0F;
  const long magnitude = std::min(roundNonNegative(std::min(std::fabs(units), 127.0F)), 127L);
  return static_cast<int8_t>(units < 0.0F ? -magnitude : magnitude);
}

}  // namespace

MeshBlock encodeMeshBlock(const render::BlockMesh& mesh, uint64_t revision) {
  const render::LabeledMesh& m = mesh.mesh;
  MeshBlock block;
  block.origin = {mesh.origin.x(), mesh.origin.y(), mesh.origin.z()};
  block.revision = revision;
  block.own_vertices = mesh.own_vertices;
  const std::size_t n = m.vertices.size();
  block.positions.reserve(3 * n);
  block.normals.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (int axis = 0; axis < 3; ++axis) {
      block.positions.push_back(positionUnits(m.vertices[i][axis]));
      block.normals.push_back(normalUnits(m.normals[i][axis]));
    }
  block.labels = m.labels;
  block.scores = m.scores;
  if (!m.colors.empty()) {
    block.colors.reserve(3 * n);
    for (const volume::Rgb8& c : m.colors) block.colors.insert(block.colors.end(), {c.r, c.g, c.b});
  }
  block.triangles.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (uint32_t index : t) block.triangles.push_back(static_cast<uint16_t>(index));
  return block;
}

}  // namespace semfuse::server
