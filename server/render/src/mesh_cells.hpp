#pragma once
// Which voxel cells the surface crosses, leaf by leaf, as bit masks: the first pass of the surface
// nets mesher (mesh_surface_nets.cpp). A cell is named by its lowest corner voxel and spans the
// 2x2x2 voxels from there, so the cells of a leaf reach one voxel into its +x, +y and +z
// neighbours (and the quads of its lower faces join cells of its -x, -y, -z ones). A cell carries
// a vertex (one per piece of surface in it, see CellTopology) when its 8 corners are all
// observed and some, not all, lie inside (tsdf < 0):
// unobserved voxels never take part, so no surface is made up against space the camera has not
// seen.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <openvdb/openvdb.h>

#include "leaf_index.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

using GeometryTree = volume::GeometryGrid::TreeType;
using GeometryLeaf = GeometryTree::LeafNodeType;
inline constexpr int kLeafDim = GeometryLeaf::DIM;  // 8
static_assert(kLeafDim == 8, "the cell masks hold one 64-bit word per x slice of an 8^3 leaf");

// Voxel offset inside a leaf buffer: OpenVDB stores z fastest.
constexpr int leafOffset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }

// The geometry leaves in tree order, and each one's 26 neighbours (looked up once, in parallel).
class LeafTable {
 public:
  static constexpr uint32_t kNone = LeafIndex::kNone;

  explicit LeafTable(const GeometryTree& tree);
  std::size_t size() const { return leaves_.size(); }
  const GeometryLeaf& leaf(std::size_t i) const { return *leaves_[i]; }
  // The leaf one leaf away from leaf i by (dx, dy, dz), each -1, 0 or 1; kNone where unallocated.
  uint32_t neighbour(std::size_t i, int dx, int dy, int dz) const {
    return neighbours_[i][9 * (dx + 1) + 3 * (dy + 1) + (dz + 1)];
  }

 private:
  std::vector<const GeometryLeaf*> leaves_;
  std::vector<std::array<uint32_t, 27>> neighbours_;
};

// Packed voxels (x, y, z), -1 <= x, y, z <= 8, of a leaf and its neighbours (the cells read 0..8;
// -1 is there for callers that look one voxel below). Unallocated neighbours read as unobserved.
class VoxelBlock {
 public:
  VoxelBlock(const LeafTable& leaves, std::size_t i);
  volume::PackedVoxel at(int x, int y, int z) const {
    const volume::PackedVoxel* data = data_[(x >> 3) + 1][(y >> 3) + 1][(z >> 3) + 1];
    return data ? data[leafOffset(x & 7, y & 7, z & 7)] : volume::kUnobservedVoxel;
  }
  // Voxels (x, y, 0..7) in a row, or null where their leaf is unallocated.
  const volume::PackedVoxel* column(int x, int y) const {
    const volume::PackedVoxel* data = data_[(x >> 3) + 1][(y >> 3) + 1][1];
    return data ? data + leafOffset(x & 7, y & 7, 0) : nullptr;
  }

 private:
  const volume::PackedVoxel* data_[3][3][3];  // [x / 8 + 1][y / 8 + 1][z / 8 + 1]
};

// How the zero level splits a cell, by which of its corners are inside (bit k = corner
// k = dx + 2 dy + 4 dz). Outside corners joined by a cell edge form one component, and each
// component is cut off by its own piece of surface, with its own vertex: outside corners that
// only share a face diagonal (a face whose signs alternate, as where a surface lies on a voxel
// layer and noise flips the signs of that layer) are kept apart. With one vertex for all pieces,
// that vertex sits near the face centre, straight above or below the vertex of the cell across
// the face, and the quads around the face's crossed edges stand perpendicular to the surface
// (half of them facing against the gradient). Both cells sharing a face see the same four
// corners on it, so the pieces always meet. Outside rather than inside corners are kept apart
// because the vertices then match OpenVDB VolumeToMesh's (on the test scene 96.9% lie within a
// tenth of a voxel of one of its vertices, against 84% the other way round).
struct CellTopology {
  int8_t group[8][3];  // [corner k][axis]: piece of the edge from k towards +axis; -1 where not crossed
  uint8_t groups;      // pieces of surface in the cell, 0..4
};
const std::array<CellTopology, 256>& cellTopologies();  // indexed by inside corners
inline const CellTopology& cellTopology(uint8_t inside_corners) { return cellTopologies()[inside_corners]; }

// The cells of one leaf that carry a vertex, and where their vertices go in the mesh.
struct LeafCells {
  static constexpr int kBlock = kLeafDim + 1;  // voxels per axis that the leaf's cells touch

  std::array<uint64_t, kLeafDim> surface{};  // word x, bit 8y + z: cell (x, y, z) carries a vertex
  // Bit z of [kBlock * x + y]: voxel (x, y, z), 0 <= x, y, z <= 8, is observed and inside.
  std::array<uint16_t, kBlock * kBlock> inside{};
  std::array<uint32_t, kLeafDim> vertices_before_word{};  // vertices in words 0..x-1
  // Cells with more than one piece of surface (CellTopology): their first piece's vertex is
  // numbered with the others, the further ones after all of those, in the order of the cells.
  std::array<uint64_t, kLeafDim> split{};
  struct SplitCell {
    uint16_t cell;         // 64 x + 8 y + z
    uint32_t first_extra;  // extra vertices of the split cells before this one
  };
  std::vector<SplitCell> split_cells;  // by cell; a few per leaf at most
  uint32_t single_count = 0;           // vertices numbered by the surface bits
  uint32_t vertex_count = 0;           // those and the extra ones
  uint32_t first_vertex = 0;           // index in the mesh of the leaf's first vertex, set once all are counted

  bool isSurface(int x, int y, int z) const { return (surface[x] >> ((y << 3) | z)) & 1; }
  bool isSplit(int x, int y, int z) const { return (split[x] >> ((y << 3) | z)) & 1; }
  bool isInside(int x, int y, int z) const { return (inside[kBlock * x + y] >> z) & 1; }
  // Bit k: corner k = dx + 2 dy + 4 dz of cell (x, y, z) is inside.
  uint8_t insideCorners(int x, int y, int z) const {
    // Bits z and z + 1 of column (x + dx, y + dy) are corners dx + 2 dy and dx + 2 dy + 4.
    auto pair = [&](int dx, int dy) {
      const unsigned bits = (inside[kBlock * (x + dx) + y + dy] >> z) & 3u;
      return ((bits & 1u) | ((bits & 2u) << 3)) << (dx + 2 * dy);
    };
    return static_cast<uint8_t>(pair(0, 0) | pair(1, 0) | pair(0, 1) | pair(1, 1));
  }
  // Mesh index of the (first) vertex of cell (x, y, z), which must carry one: vertices are
  // numbered in the order of the bits.
  uint32_t vertex(int x, int y, int z) const {
    const int bit = (y << 3) | z;
    return first_vertex + vertices_before_word[x] +
           static_cast<uint32_t>(__builtin_popcountll(surface[x] & ((uint64_t{1} << bit) - 1)));
  }
  // Mesh index of the vertex of piece `group` > 0 of split cell (x, y, z).
  [[gnu::pure]] uint32_t extraVertex(int x, int y, int z, int group) const;
  // Mesh index of the vertex whose piece crosses the edge from corner k of cell (x, y, z)
  // towards +axis; that edge must be crossed. Split cells take the out-of-line path, so that
  // the common one stays small enough to inline into the quad loop.
  [[gnu::always_inline]] uint32_t edgeVertex(int x, int y, int z, int k, int axis) const {
    return isSplit(x, y, z) ? splitEdgeVertex(x, y, z, k, axis) : vertex(x, y, z);
  }
  // Pure, so that where only the count of quads is wanted the compiler drops the call.
  [[gnu::pure]] uint32_t splitEdgeVertex(int x, int y, int z, int k, int axis) const;
};

// Cells of leaf i that carry a vertex; with cell_bounds, only cells inside it.
LeafCells classifyCells(const LeafTable& leaves, std::size_t i, const std::optional<openvdb::CoordBBox>& cell_bounds);

}  // namespace semfuse::render::detail
