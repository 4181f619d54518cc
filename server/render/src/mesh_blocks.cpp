#include "semfuse/render/mesh_blocks.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "block_cells.hpp"
#include "block_voxels.hpp"
#include "mesh_vertex.hpp"

namespace semfuse::render {
namespace {

using detail::BlockCells;
using detail::BlockVoxels;
using detail::CellCorners;
using detail::CellTopology;
constexpr int kDim = detail::kLeafDim;       // voxels per block side
constexpr int kCells = detail::kBlockCells;  // cells per side whose vertices a block may use
constexpr std::size_t kBlocksPerTask = 8;

// One block's surface nets, in the block's own coordinates, from its classified cells.
class BlockMesher {
 public:
  BlockMesher(const BlockVoxels& voxels, const BlockCells& cells, bool with_colors, float voxel_size, BlockMesh& out)
      : voxels_(voxels),
        cells_(cells),
        with_colors_(with_colors),
        voxel_size_(voxel_size),
        origin_(out.origin),
        mesh_(out.mesh) {
    first_vertex_.fill(-1);
    reserve();
    // The block's own cells first, in order, so that its own vertices come first.
    forEachOwnSurfaceCell([this](int x, int y, int z) { addVertices(x, y, z); });
    out.own_vertices = static_cast<uint32_t>(mesh_.vertices.size());
    forEachOwnSurfaceCell([this](int x, int y, int z) { addQuads(x, y, z); });
  }

 private:
  // In x, y, z order, visiting only the set bits.
  template <class Fn>
  void forEachOwnSurfaceCell(Fn&& fn) const {
    for (int x = 0; x < kDim; ++x)
      for (int y = 0; y < kDim; ++y)
        for (unsigned bits = cells_.surface[x][y] & 0xFFu; bits != 0; bits &= bits - 1) fn(x, y, __builtin_ctz(bits));
  }

  // Room for what a block usually holds (one vertex per own cell and some from the layer above,
  // two triangles per cell), so that its arrays grow once rather than doubling their way there.
  void reserve() {
    std::size_t cells = 0;
    for (int x = 0; x < kDim; ++x)
      for (int y = 0; y < kDim; ++y)
        cells += static_cast<std::size_t>(__builtin_popcount(cells_.surface[x][y] & 0xFFu));
    const std::size_t vertices = cells + cells / 4 + 8;
    mesh_.vertices.reserve(vertices);
    mesh_.normals.reserve(vertices);
    mesh_.labels.reserve(vertices);
    mesh_.scores.reserve(vertices);
    if (with_colors_) mesh_.colors.reserve(vertices);
    world_.reserve(vertices);
    mesh_.triangles.reserve(2 * cells + 8);
  }

  bool isSurface(int x, int y, int z) const { return cells_.isSurface(x, y, z); }
  bool isInside(int x, int y, int z) const { return cells_.isInside(x, y, z); }
  static int cellIndex(int x, int y, int z) { return (x * kCells + y) * kCells + z; }

  CellCorners corners(int x, int y, int z) const {
    CellCorners c;
    for (int k = 0; k < 8; ++k) c.packed[k] = voxels_.at(x + (k & 1), y + ((k >> 1) & 1), z + ((k >> 2) & 1));
    detail::fillCorners(c);
    return c;
  }
  static uint8_t insideMask(const CellCorners& c) {
    uint8_t mask = 0;
    for (int k = 0; k < 8; ++k) mask |= static_cast<uint8_t>(c.inside[k] ? 1u << k : 0u);
    return mask;
  }

  // One vertex per piece of surface in the cell, numbered consecutively.
  void addVertices(int x, int y, int z) {
    const CellCorners c = corners(x, y, z);
    const CellTopology& topology = topologies_[insideMask(c)];
    const auto cell_index = static_cast<std::size_t>(cellIndex(x, y, z));
    first_vertex_[cell_index] = static_cast<int>(mesh_.vertices.size());
    pieces_[cell_index] = topology.groups;
    for (int group = 0; group < topology.groups; ++group) {
      const Eigen::Vector3f p =
          topology.groups == 1 ? detail::meanCrossing(c) : detail::meanCrossing(c, &topology, group);
      mesh_.vertices.emplace_back(Eigen::Vector3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)) +
                                  p);
      // The world position as extractMesh computes it, bit for bit, for the quads' split.
      const openvdb::Coord cell = origin_.offsetBy(x, y, z);
      world_.emplace_back(
          (Eigen::Vector3f(static_cast<float>(cell.x()), static_cast<float>(cell.y()), static_cast<float>(cell.z())) +
           p) *
          voxel_size_);
      mesh_.normals.push_back(detail::normalAt(c, p));
      const int nearest = detail::nearestCorner(p);
      mesh_.labels.push_back(volume::unpackLabel(c.packed[nearest]));
      mesh_.scores.push_back(volume::unpackScore(c.packed[nearest]));
      if (with_colors_)
        mesh_.colors.push_back(voxels_.color(x + (nearest & 1), y + ((nearest >> 1) & 1), z + ((nearest >> 2) & 1)));
    }
  }

  // The vertex of cell (x, y, z) whose piece crosses the edge from its corner k along `axis`;
  // cells of the layer above the block get their vertices when a quad first needs them.
  uint32_t edgeVertex(int x, int y, int z, int k, int axis) {
    const auto cell_index = static_cast<std::size_t>(cellIndex(x, y, z));
    if (first_vertex_[cell_index] < 0) addVertices(x, y, z);
    const auto first = static_cast<uint32_t>(first_vertex_[cell_index]);
    // A cell with one piece of surface has one vertex for all its crossed edges.
    if (pieces_[cell_index] == 1) return first;
    const int group = topologies_[cells_.insideCorners(x, y, z)].group[k][axis];
    return first + static_cast<uint32_t>(std::max(group, 0));
  }

  // The quads of the crossed edges whose lowest surrounding cell is (x, y, z): the edge from voxel
  // v = (x, y, z) + u + w along each axis, u and w the other two. The four cells are listed as
  // extractMesh's surface nets lists them, counter-clockwise seen from the free side.
  void addQuads(int x, int y, int z) {
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<int, 3> c0{x, y, z};
      std::array<int, 3> v = c0;
      for (int other = 0; other < 3; ++other)
        if (other != axis) ++v[other];
      std::array<int, 3> beyond = v;
      ++beyond[axis];
      const bool inside = isInside(v[0], v[1], v[2]);
      if (inside == isInside(beyond[0], beyond[1], beyond[2])) continue;
      // Around the edge, by extractMesh's listing: a = v - u - w, then b, d and c = v.
      std::array<std::array<int, 3>, 4> cells;
      auto minus = [&](int dx, int dy, int dz) { return std::array<int, 3>{v[0] - dx, v[1] - dy, v[2] - dz}; };
      if (axis == 0) cells = {minus(0, 1, 1), minus(0, 0, 1), v, minus(0, 1, 0)};
      else if (axis == 1) cells = {minus(1, 0, 1), minus(1, 0, 0), v, minus(0, 0, 1)};
      else cells = {minus(1, 1, 0), minus(0, 1, 0), v, minus(1, 0, 0)};
      bool all = true;
      for (const auto& cell : cells) all = all && isSurface(cell[0], cell[1], cell[2]);
      if (!all) continue;
      std::array<uint32_t, 4> index;
      for (int q = 0; q < 4; ++q) {
        const auto& cell = cells[q];
        const int k = (v[0] - cell[0]) | ((v[1] - cell[1]) << 1) | ((v[2] - cell[2]) << 2);
        index[q] = edgeVertex(cell[0], cell[1], cell[2], k, axis);
      }
      if (inside) emit(index[0], index[1], index[2], index[3]);
      else emit(index[0], index[3], index[2], index[1]);
    }
  }

  // Split as extractMesh splits: on the same world positions, so that both choose the same
  // diagonal (in block coordinates the rounding differs and near-ties could go the other way).
  void emit(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    const auto& p = world_;
    if (detail::splitAlongAC(p[a], p[b], p[c], p[d])) {
      mesh_.triangles.push_back({a, b, c});
      mesh_.triangles.push_back({a, c, d});
    } else {
      mesh_.triangles.push_back({a, b, d});
      mesh_.triangles.push_back({b, c, d});
    }
  }

  const BlockVoxels& voxels_;
  const BlockCells& cells_;
  bool with_colors_;
  float voxel_size_;
  openvdb::Coord origin_;
  LabeledMesh& mesh_;
  std::vector<Eigen::Vector3f> world_;  // per vertex
  const std::array<CellTopology, 256>& topologies_ = detail::cellTopologies();
  std::array<int, kCells * kCells * kCells> first_vertex_{};  // -1: no vertex yet
  std::array<uint8_t, kCells * kCells * kCells> pieces_;      // of surface; set with first_vertex_
};

// Division rounding towards minus infinity (block and leaf origins may be negative).
int floorDiv(int a, int b) { return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0); }
int ceilDiv(int a, int b) { return -floorDiv(-a, b); }

}  // namespace

std::vector<openvdb::Coord> blocksReadingLeaves(const std::vector<openvdb::Coord>& leaf_origins, int stride) {
  stride = std::clamp(stride, 1, detail::kMaxBlockStride);
  // Along one axis, the block origins b (multiples of 8) whose map voxels [s b, s b + 9 s] meet
  // the leaf's [l, l + 7]: from ceil((l - 9 s) / s) to floor((l + 7) / s).
  auto along = [stride](int l, int(&out)[4]) {
    const int first = floorDiv(ceilDiv(l - (kDim + 1) * stride, stride) + kDim - 1, kDim) * kDim;
    const int last = floorDiv(floorDiv(l + kDim - 1, stride), kDim) * kDim;
    int n = 0;
    for (int b = first; b <= last && n < 4; b += kDim) out[n++] = b;
    return n;
  };
  std::vector<openvdb::Coord> blocks;
  blocks.reserve(leaf_origins.size() * 8);
  for (const openvdb::Coord& leaf : leaf_origins) {
    int xs[4], ys[4], zs[4];
    const int nx = along(leaf.x(), xs), ny = along(leaf.y(), ys), nz = along(leaf.z(), zs);
    for (int i = 0; i < nx; ++i)
      for (int j = 0; j < ny; ++j)
        for (int k = 0; k < nz; ++k) blocks.emplace_back(xs[i], ys[j], zs[k]);
  }
  std::sort(blocks.begin(), blocks.end());
  blocks.erase(std::unique(blocks.begin(), blocks.end()), blocks.end());
  return blocks;
}

struct GatheredBlocks::Block {
  detail::BlockCells cells;
  detail::BlockVoxelCopy voxels;
};

GatheredBlocks::GatheredBlocks() = default;
GatheredBlocks::GatheredBlocks(GatheredBlocks&&) noexcept = default;
GatheredBlocks& GatheredBlocks::operator=(GatheredBlocks&&) noexcept = default;
GatheredBlocks::~GatheredBlocks() = default;
std::size_t GatheredBlocks::size() const { return origins_.size(); }
std::size_t GatheredBlocks::withSurface() const {
  return static_cast<std::size_t>(
      std::count_if(blocks_.begin(), blocks_.end(), [](const auto& block) { return block != nullptr; }));
}

GatheredBlocks gatherBlocks(const volume::LabeledVolume& volume, const std::vector<openvdb::Coord>& origins,
                            int stride) {
  stride = std::clamp(stride, 1, detail::kMaxBlockStride);
  GatheredBlocks gathered;
  gathered.origins_ = origins;
  gathered.blocks_.resize(origins.size());
  gathered.with_colors_ = volume.hasColor() && volume.colorGrid() != nullptr;
  gathered.voxel_size_ = static_cast<float>(volume.voxelSize() * stride);
  const bool with_colors = gathered.with_colors_;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, origins.size(), kBlocksPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      // Unregistered accessors: the volume cannot change under the caller's lock,
                      // and registering one with the tree per task costs a lock of its own.
                      const auto geometry = volume.geometryGrid().getConstUnsafeAccessor();
                      std::optional<volume::ColorGrid::ConstUnsafeAccessor> colors;
                      if (with_colors) colors.emplace(volume.colorGrid()->getConstUnsafeAccessor());
                      BlockVoxels voxels(stride);
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        const openvdb::Coord in_map(origins[i].asVec3i() * stride);
                        if (!voxels.gather(geometry, in_map)) continue;
                        const BlockCells cells = detail::classifyBlockCells(voxels);
                        if (!cells.hasOwnSurface()) continue;  // most blocks an update re-meshes
                        if (colors) voxels.gatherColors(*colors, in_map);
                        // Not value-initialised: copyTo writes what meshing reads.
                        std::unique_ptr<GatheredBlocks::Block> block(new GatheredBlocks::Block);
                        block->cells = cells;
                        voxels.copyTo(block->voxels, with_colors);
                        gathered.blocks_[i] = std::move(block);
                      }
                    });
  return gathered;
}

std::vector<BlockMesh> meshGatheredBlocks(const GatheredBlocks& gathered) {
  std::vector<BlockMesh> blocks(gathered.origins_.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size(), kBlocksPerTask),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i < range.end(); ++i) {
                        blocks[i].origin = gathered.origins_[i];
                        const GatheredBlocks::Block* block = gathered.blocks_[i].get();
                        if (block == nullptr) continue;
                        const BlockVoxels voxels(block->voxels);
                        BlockMesher{voxels, block->cells, gathered.with_colors_, gathered.voxel_size_, blocks[i]};
                      }
                    });
  return blocks;
}

std::vector<BlockMesh> extractBlockMeshes(const volume::LabeledVolume& volume,
                                          const std::vector<openvdb::Coord>& origins, int stride) {
  return meshGatheredBlocks(gatherBlocks(volume, origins, stride));
}

}  // namespace semfuse::render
