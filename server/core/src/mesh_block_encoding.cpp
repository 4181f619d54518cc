#include "mesh_block_encoding.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

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

MeshBlock encodeMeshBlock(render::BlockMesh mesh, uint64_t revision) {
  render::LabeledMesh& m = mesh.mesh;
  MeshBlock block;
  block.origin = {mesh.origin.x(), mesh.origin.y(), mesh.origin.z()};
  block.revision = revision;
  block.own_vertices = mesh.own_vertices;
  const std::size_t n = m.vertices.size();
  block.positions.resize(3 * n);
  block.normals.resize(3 * n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t axis = 0; axis < 3; ++axis) {
      block.positions[3 * i + axis] = positionUnits(m.vertices[i][axis]);
      block.normals[3 * i + axis] = normalUnits(m.normals[i][axis]);
    }
  block.labels = std::move(m.labels);
  block.scores = std::move(m.scores);
  if (!m.colors.empty()) {
    block.colors.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      block.colors[3 * i] = m.colors[i].r;
      block.colors[3 * i + 1] = m.colors[i].g;
      block.colors[3 * i + 2] = m.colors[i].b;
    }
  }
  block.triangles.resize(3 * m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (std::size_t corner = 0; corner < 3; ++corner)
      block.triangles[3 * t + corner] = static_cast<uint16_t>(m.triangles[t][corner]);
  return block;
}

}  // namespace semfuse::server
