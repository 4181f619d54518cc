#include "mesh_surface_nets.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <Eigen/Geometry>

#include "mesh_cells.hpp"
#include "mesh_vertex.hpp"

namespace semfuse::render::detail {
namespace {

constexpr std::size_t kLeavesPerTask = 16;

CellCorners gatherCorners(const VoxelBlock& block, int x, int y, int z) {
  CellCorners corners;
  for (int k = 0; k < 8; ++k) corners.packed[k] = block.at(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
  fillCorners(corners);
  return corners;
}

// Writes vertex `index` at p in the cell, with the normal there and label, score and colour of
// the nearest corner.
void placeVertex(const CellCorners& corners, const openvdb::Coord& cell, const Eigen::Vector3f& p, float voxel_size,
                 volume::ColorGrid::ConstAccessor* colors, uint32_t index, LabeledMesh& mesh) {
  mesh.vertices[index] =
      (Eigen::Vector3f(static_cast<float>(cell.x()), static_cast<float>(cell.y()), static_cast<float>(cell.z())) + p) *
      voxel_size;
  mesh.normals[index] = normalAt(corners, p);
  const int nearest = nearestCorner(p);
  mesh.labels[index] = volume::unpackLabel(corners.packed[nearest]);
  mesh.scores[index] = volume::unpackScore(corners.packed[nearest]);
  if (colors)
    mesh.colors[index] =
        volume::unpackColor(colors->getValue(cell.offsetBy(nearest & 1, (nearest >> 1) & 1, (nearest >> 2) & 1)));
}

// Writes position, normal, label, score and colour of every vertex of leaf i, at the indices
// LeafCells::vertex gives.
void placeVertices(const volume::LabeledVolume& volume, const LeafTable& leaves, std::size_t i, const LeafCells& cells,
                   volume::ColorGrid::ConstAccessor* colors, LabeledMesh& mesh) {
  const VoxelBlock block(leaves, i);
  const openvdb::Coord origin = leaves.leaf(i).origin();
  const auto voxel_size = static_cast<float>(volume.voxelSize());
  uint32_t index = cells.first_vertex;
  for (int x = 0; x < kLeafDim; ++x)
    for (uint64_t word = cells.surface[x]; word != 0; word &= word - 1, ++index) {
      const int bit = __builtin_ctzll(word);
      const int y = bit >> 3, z = bit & 7;
      const CellCorners corners = gatherCorners(block, x, y, z);
      const openvdb::Coord cell = origin.offsetBy(x, y, z);
      if (!cells.isSplit(x, y, z)) {
        placeVertex(corners, cell, meanCrossing(corners), voxel_size, colors, index, mesh);
        continue;
      }
      const CellTopology& topology = cellTopology(cells.insideCorners(x, y, z));
      for (int group = 0; group < topology.groups; ++group)
        placeVertex(corners, cell, meanCrossing(corners, &topology, group), voxel_size, colors,
                    group == 0 ? index : cells.extraVertex(x, y, z, group), mesh);
    }
}

// The cells of a leaf and of its -x, -y, -z neighbours: a quad joins the four cells around an
// edge, and for edges on the leaf's lower faces some of them lie in those neighbours.
class LowerCells {
 public:
  LowerCells(const LeafTable& leaves, const std::vector<LeafCells>& cells, std::size_t i) {
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 2; ++c) {
          const uint32_t n = leaves.neighbour(i, -a, -b, -c);
          around_[a][b][c] = n == LeafTable::kNone ? nullptr : &cells[n];
        }
  }
  // Mesh index of the vertex of cell (x, y, z), -1 <= x, y, z <= 7 in the leaf's coordinates,
  // whose piece crosses the edge from the cell's corner k towards +axis.
  [[gnu::always_inline]] bool vertex(int x, int y, int z, int k, int axis, uint32_t& index) const {
    const LeafCells* owner = around_[x < 0][y < 0][z < 0];
    if (owner == nullptr || !owner->isSurface(x & 7, y & 7, z & 7)) return false;
    index = owner->edgeVertex(x & 7, y & 7, z & 7, k, axis);
    return true;
  }

 private:
  const LeafCells* around_[2][2][2];  // [x < 0][y < 0][z < 0]
};

// Calls emit(a, b, c, d) for every crossed voxel edge that starts at a voxel of leaf i and whose
// four cells all carry a vertex, with their vertex indices counter-clockwise seen from the free
// (tsdf > 0) side. The edge from voxel v along an axis is surrounded by the cells whose lowest
// corners are v, v - u, v - w and v - u - w, u and w the other two axes: cell v is the one the
// loop is at, so every such edge is visited exactly once, from a cell that carries a vertex.
// Inlined into both passes, so that the counting pass drops the vertex index lookups.
template <typename Emit>
[[gnu::always_inline]] inline void forEachQuad(const LeafTable& leaves, const std::vector<LeafCells>& all_cells,
                                               std::size_t i, Emit&& emit) {
  const LeafCells& cells = all_cells[i];
  const LowerCells lower(leaves, all_cells, i);
  uint32_t self = cells.first_vertex;
  for (int x = 0; x < kLeafDim; ++x)
    for (uint64_t word = cells.surface[x]; word != 0; word &= word - 1, ++self) {
      const int bit = __builtin_ctzll(word);
      const int y = bit >> 3, z = bit & 7;
      const bool inside = cells.isInside(x, y, z);
      // Listed (a, b, self, d) so that they turn counter-clockwise around +axis: seen from the
      // + end of the edge. That end is the free side when v is inside; otherwise reverse.
      // The edge starts at the corner of cell (cx, cy, cz) that lies at (x, y, z).
      auto corner = [&](int cx, int cy, int cz) { return (x - cx) | ((y - cy) << 1) | ((z - cz) << 2); };
      auto quad = [&](int axis, bool crossed, int ax, int ay, int az, int bx, int by, int bz, int dx, int dy, int dz) {
        uint32_t a, b, d;
        if (!crossed || !lower.vertex(ax, ay, az, corner(ax, ay, az), axis, a) ||
            !lower.vertex(bx, by, bz, corner(bx, by, bz), axis, b) ||
            !lower.vertex(dx, dy, dz, corner(dx, dy, dz), axis, d))
          return;
        const uint32_t c = cells.isSplit(x, y, z) ? cells.splitEdgeVertex(x, y, z, 0, axis) : self;
        if (inside) emit(a, b, c, d);
        else emit(a, d, c, b);
      };
      quad(0, cells.isInside(x + 1, y, z) != inside, x, y - 1, z - 1, x, y, z - 1, x, y - 1, z);
      quad(1, cells.isInside(x, y + 1, z) != inside, x - 1, y, z - 1, x - 1, y, z, x, y, z - 1);
      quad(2, cells.isInside(x, y, z + 1) != inside, x - 1, y - 1, z, x, y - 1, z, x - 1, y, z);
    }
}

template <typename Body>
void forEachLeaf(std::size_t count, Body&& body) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kLeavesPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) { body(range); });
}

}  // namespace

Result<LabeledMesh> surfaceNetsMesh(const volume::LabeledVolume& volume,
                                    const std::optional<openvdb::CoordBBox>& cell_bounds) {
  LabeledMesh mesh;
  const LeafTable leaves(volume.geometryGrid().tree());
  const std::size_t leaf_count = leaves.size();

  // Pass 1: which cells carry a vertex; then number the vertices leaf after leaf.
  std::vector<LeafCells> cells(leaf_count);
  forEachLeaf(leaf_count, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) cells[i] = classifyCells(leaves, i, cell_bounds);
  });
  uint64_t vertex_count = 0;
  for (LeafCells& c : cells) {
    c.first_vertex = static_cast<uint32_t>(vertex_count);
    vertex_count += c.vertex_count;
  }
  if (vertex_count > std::numeric_limits<uint32_t>::max())
    return makeError("mesh too large: " + std::to_string(vertex_count) + " vertices");

  // Pass 2: vertices with their attributes, and how many quads each leaf will emit.
  mesh.vertices.resize(vertex_count);
  mesh.normals.resize(vertex_count);
  mesh.labels.resize(vertex_count);
  mesh.scores.resize(vertex_count);
  if (volume.hasColor() && volume.colorGrid()) mesh.colors.resize(vertex_count);
  std::vector<uint64_t> first_quad(leaf_count + 1, 0);
  forEachLeaf(leaf_count, [&](const tbb::blocked_range<std::size_t>& range) {
    std::optional<volume::ColorGrid::ConstAccessor> colors;
    if (!mesh.colors.empty()) colors.emplace(volume.colorGrid()->getConstAccessor());
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (cells[i].vertex_count == 0) continue;
      placeVertices(volume, leaves, i, cells[i], colors ? &*colors : nullptr, mesh);
      uint64_t quads = 0;
      forEachQuad(leaves, cells, i, [&](uint32_t, uint32_t, uint32_t, uint32_t) { ++quads; });
      first_quad[i + 1] = quads;
    }
  });
  for (std::size_t i = 0; i < leaf_count; ++i) first_quad[i + 1] += first_quad[i];

  // Pass 3: the triangles, two per quad, leaf after leaf.
  mesh.triangles.resize(2 * first_quad[leaf_count]);
  forEachLeaf(leaf_count, [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      if (cells[i].vertex_count == 0) continue;
      std::array<uint32_t, 3>* out = mesh.triangles.data() + 2 * first_quad[i];
      forEachQuad(leaves, cells, i, [&](uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
        if (splitAlongAC(mesh.vertices[a], mesh.vertices[b], mesh.vertices[c], mesh.vertices[d])) {
          *out++ = {a, b, c};
          *out++ = {a, c, d};
        } else {
          *out++ = {a, b, d};
          *out++ = {b, c, d};
        }
      });
    }
  });
  return mesh;
}

}  // namespace semfuse::render::detail
