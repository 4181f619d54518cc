// The block mesher (render/mesh_blocks.hpp) against the whole-map surface nets: together the
// blocks make exactly extractMesh's triangles and vertices, neighbouring blocks meet without a
// seam, and after a change re-meshing only blocksReadingLeaves(changed leaves) gives the mesh of
// the changed map.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "fused_scene.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/mesh_blocks.hpp"

namespace semfuse::render {
namespace {

using testing::kVoxel;

// The whole mesh's vertices, found again from points computed elsewhere (in block coordinates)
// within a thousandth of a voxel: the pieces of the block meshes named by the whole mesh's
// vertex indices.
class VertexIndex {
 public:
  explicit VertexIndex(const LabeledMesh& whole, double voxel = kVoxel) {
    for (uint32_t i = 0; i < whole.vertices.size(); ++i) {
      points_.push_back(whole.vertices[i].cast<double>() / voxel);
      cells_[cellOf(points_.back())].push_back(i);
    }
  }
  // The whole mesh's vertex nearest to `voxels` within a thousandth of a voxel, or -1. (The
  // vertices of a split cell and its neighbours can lie closer together than that, but the same
  // vertex computed in block and in world coordinates differs by about 1e-5 voxel.)
  int64_t find(const Eigen::Vector3d& voxels) const {
    int64_t best = -1;
    double best_distance = 1e-3;
    const auto [cx, cy, cz] = cellOf(voxels);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find({cx + dx, cy + dy, cz + dz});
          if (it == cells_.end()) continue;
          for (uint32_t i : it->second) {
            const double distance = (points_[i] - voxels).norm();
            if (distance < best_distance) {
              best = i;
              best_distance = distance;
            }
          }
        }
    return best;
  }

 private:
  using Cell = std::tuple<int64_t, int64_t, int64_t>;
  static Cell cellOf(const Eigen::Vector3d& p) {
    return {std::llround(p.x() * 100.0), std::llround(p.y() * 100.0), std::llround(p.z() * 100.0)};
  }
  std::vector<Eigen::Vector3d> points_;
  std::map<Cell, std::vector<uint32_t>> cells_;
};

// A triangle as its vertex indices, starting at the smallest, turning the same way.
using TriangleKey = std::array<int64_t, 3>;
TriangleKey triangleKey(int64_t a, int64_t b, int64_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

// The pieces of a mesh, named by the whole mesh's vertex indices (-1: none there).
struct MeshKeys {
  std::multiset<TriangleKey> triangles;
  std::multiset<int64_t> vertices;
};

MeshKeys wholeKeys(const LabeledMesh& mesh) {
  MeshKeys keys;
  for (uint32_t i = 0; i < mesh.vertices.size(); ++i) keys.vertices.insert(i);
  for (const auto& t : mesh.triangles) keys.triangles.insert(triangleKey(t[0], t[1], t[2]));
  return keys;
}

Eigen::Vector3d blockPoint(const BlockMesh& block, uint32_t i) {
  return Eigen::Vector3d(block.origin.x(), block.origin.y(), block.origin.z()) + block.mesh.vertices[i].cast<double>();
}

// Own vertices and all triangles of every block.
MeshKeys blockKeys(const std::vector<BlockMesh>& blocks, const VertexIndex& whole) {
  MeshKeys keys;
  for (const BlockMesh& block : blocks) {
    std::vector<int64_t> index(block.mesh.vertices.size());
    for (uint32_t i = 0; i < index.size(); ++i) index[i] = whole.find(blockPoint(block, i));
    for (uint32_t i = 0; i < block.own_vertices; ++i) keys.vertices.insert(index[i]);
    for (const auto& t : block.mesh.triangles)
      keys.triangles.insert(triangleKey(index[t[0]], index[t[1]], index[t[2]]));
  }
  return keys;
}

std::vector<openvdb::Coord> allLeaves(const volume::LabeledVolume& volume) {
  std::vector<openvdb::Coord> leaves;
  for (auto leaf = volume.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf->origin());
  return leaves;
}

// The map seen through the lattice of every `stride`-th voxel: a volume of stride times the voxel
// whose voxel c holds the map's voxel stride * c. Its whole mesh is what the blocks of that stride
// must make.
volume::LabeledVolume sampledCopy(const volume::LabeledVolume& map, int stride) {
  volume::VolumeParams p = map.params();
  p.voxel_size *= stride;
  volume::LabeledVolume sampled(p);
  auto& tree = sampled.mutableGeometryGrid().tree();
  for (auto leaf = map.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf)
    for (auto it = leaf->cbeginValueAll(); it; ++it) {
      const openvdb::Coord c = it.getCoord();
      if (c.x() % stride != 0 || c.y() % stride != 0 || c.z() % stride != 0) continue;
      if (*it != volume::kUnobservedVoxel) tree.setValue(openvdb::Coord(c.asVec3i() / stride), *it);
    }
  return sampled;
}

// Edges used by one triangle only, after welding vertices at equal keys: the mesh's open rim.
std::size_t boundaryEdges(const std::multiset<TriangleKey>& triangles) {
  std::map<std::pair<int64_t, int64_t>, int> uses;
  for (const TriangleKey& t : triangles)
    for (int e = 0; e < 3; ++e) {
      int64_t a = t[e], b = t[(e + 1) % 3];
      if (b < a) std::swap(a, b);
      ++uses[{a, b}];
    }
  return static_cast<std::size_t>(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 1; }));
}

// The plane-and-sphere scene of mesh_test.cpp.
class BlockMeshTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    synthetic::LabeledScene scene;
    scene.add({"plane",
               synthetic::OrientedBox{{0, 0, -0.1}, {1.0, 1.0, 0.1}, Eigen::Matrix3d::Identity()},
               1,
               {200, 180, 150},
               synthetic::Texture::kChecker});
    scene.add({"sphere", synthetic::Sphere{{0.0, 0.0, 0.3}, 0.25}, 7, {200, 40, 40}, synthetic::Texture::kNoise});
    volume_ = new volume::LabeledVolume(testing::fusedVolumeParams());
    testing::fuse(*volume_, scene, testing::arcAround({0, 0, 0.2}, 1.1, 0.6, 8, 2.5));
  }
  static void TearDownTestSuite() {
    delete volume_;
    volume_ = nullptr;
  }
  static volume::LabeledVolume* volume_;
};
volume::LabeledVolume* BlockMeshTest::volume_ = nullptr;

TEST_F(BlockMeshTest, BlocksTogetherAreTheWholeMesh) {
  const LabeledMesh whole = extractMesh(*volume_).value();
  ASSERT_GT(whole.triangles.size(), 50000u);
  const std::vector<BlockMesh> blocks = extractBlockMeshes(*volume_, allLeaves(*volume_));
  const VertexIndex index(whole);
  const MeshKeys expected = wholeKeys(whole), got = blockKeys(blocks, index);

  // Every own vertex is a vertex of the whole mesh, and every vertex of the whole mesh is some
  // block's own vertex.
  EXPECT_EQ(got.vertices.size(), expected.vertices.size());
  EXPECT_EQ(got.vertices, expected.vertices);
  // The same triangles (each quad split along the same diagonal).
  EXPECT_EQ(got.triangles.size(), expected.triangles.size());
  EXPECT_EQ(got.triangles, expected.triangles);
  // Seams close: welded, the blocks leave open only the rim the whole mesh has.
  EXPECT_EQ(boundaryEdges(got.triangles), boundaryEdges(expected.triangles));

  // Attributes travel with the vertices: the block's label and normal at each own vertex equal
  // the whole mesh's at the same point.
  std::size_t compared = 0;
  for (const BlockMesh& block : blocks)
    for (uint32_t i = 0; i < block.mesh.vertices.size(); ++i) {
      const int64_t at = index.find(blockPoint(block, i));
      ASSERT_GE(at, 0);
      EXPECT_EQ(block.mesh.labels[i], whole.labels[at]);
      EXPECT_GT(block.mesh.normals[i].dot(whole.normals[at]), 0.9999f);
      ++compared;
    }
  EXPECT_GT(compared, expected.vertices.size());  // the repeated vertices of the layer above too
}

TEST_F(BlockMeshTest, ABlockStaysWithinItsLeafAndTheLayerAbove) {
  const std::vector<BlockMesh> blocks = extractBlockMeshes(*volume_, allLeaves(*volume_));
  std::size_t with_surface = 0;
  for (const BlockMesh& block : blocks) {
    const LabeledMesh& m = block.mesh;
    ASSERT_LE(block.own_vertices, m.vertices.size());
    ASSERT_LT(m.vertices.size(), 65536u);
    with_surface += m.vertices.empty() ? 0 : 1;
    for (uint32_t i = 0; i < m.vertices.size(); ++i) {
      const Eigen::Vector3f& v = m.vertices[i];
      // Own vertices lie in the block's cells [0, 8]^3, the repeated ones in the cells above: [0, 9]^3.
      const float limit = i < block.own_vertices ? 8.0f : 9.0f;
      ASSERT_TRUE(v.minCoeff() >= 0.0f && v.maxCoeff() <= limit) << v.transpose();
      if (i >= block.own_vertices) {
        EXPECT_GT(v.maxCoeff(), 8.0f - 1e-6f);
      }
    }
    for (const auto& t : m.triangles)
      for (uint32_t index : t) ASSERT_LT(index, m.vertices.size());
  }
  EXPECT_GT(with_surface, 500u);
}

TEST_F(BlockMeshTest, RemeshingTheBlocksThatReadAChangedLeafGivesTheChangedMap) {
  volume::LabeledVolume changed = volume_->deepCopy();
  std::vector<openvdb::Coord> leaves = allLeaves(changed);
  const std::vector<BlockMesh> before = extractBlockMeshes(changed, leaves);

  // Push in the surface of every 16th leaf that holds surface: each observed voxel of them gets
  // 1.5 voxels further inside (tsdf - 1.5 voxel) and label 3. Among so many, the surface crosses
  // every kind of border: faces, edges and corners of the leaves below.
  const LabeledMesh whole_before = extractMesh(changed).value();
  std::set<openvdb::Coord> surface_leaves;
  for (const Eigen::Vector3f& v : whole_before.vertices) {
    const Eigen::Vector3f at = v / kVoxel;
    auto leafStart = [](float voxels) { return static_cast<int>(std::floor(voxels)) & ~7; };
    surface_leaves.insert(openvdb::Coord(leafStart(at.x()), leafStart(at.y()), leafStart(at.z())));
  }
  std::vector<openvdb::Coord> pushed;
  std::size_t n = 0;
  for (const openvdb::Coord& origin : surface_leaves)
    if (n++ % 16 == 0) pushed.push_back(origin);
  ASSERT_GT(pushed.size(), 20u);
  for (const openvdb::Coord& origin : pushed) {
    auto* leaf = changed.mutableGeometryGrid().tree().probeLeaf(origin);
    ASSERT_NE(leaf, nullptr);
    for (auto it = leaf->beginValueOn(); it; ++it) {
      const volume::VoxelValue v = volume::unpackVoxel(*it);
      it.setValue(volume::packVoxel(v.tsdf - 1.5f * static_cast<float>(kVoxel), v.weight, 3, v.score));
    }
  }

  const std::vector<openvdb::Coord> dirty = blocksReadingLeaves(pushed);
  EXPECT_LE(dirty.size(), 8 * pushed.size());
  std::map<openvdb::Coord, BlockMesh> blocks;
  for (const BlockMesh& b : before) blocks[b.origin] = b;
  for (BlockMesh& b : extractBlockMeshes(changed, dirty)) blocks[b.origin] = std::move(b);
  std::vector<BlockMesh> merged;
  for (auto& [origin, b] : blocks) merged.push_back(std::move(b));

  const LabeledMesh whole_after = extractMesh(changed).value();
  const VertexIndex index(whole_after);
  const MeshKeys expected = wholeKeys(whole_after), got = blockKeys(merged, index);
  EXPECT_NE(whole_before.vertices, whole_after.vertices);  // the change shows
  EXPECT_EQ(got.vertices, expected.vertices);
  EXPECT_EQ(got.triangles, expected.triangles);
}

// At stride 2 the blocks sample every other voxel: together they make exactly the surface nets of
// the map sampled so (a 2 cm volume from the 1 cm one), with about a quarter of the vertices.
TEST_F(BlockMeshTest, BlocksAtStrideTwoAreTheSurfaceOfTheSampledMap) {
  constexpr int kStride = 2;
  const volume::LabeledVolume sampled = sampledCopy(*volume_, kStride);
  const LabeledMesh whole = extractMesh(sampled).value();
  const LabeledMesh fine = extractMesh(*volume_).value();
  ASSERT_GT(whole.vertices.size(), 5000u);
  EXPECT_LT(whole.vertices.size(), fine.vertices.size() / 3);

  const std::vector<BlockMesh> blocks =
      extractBlockMeshes(*volume_, blocksReadingLeaves(allLeaves(*volume_), kStride), kStride);
  const VertexIndex index(whole, kVoxel * kStride);
  const MeshKeys expected = wholeKeys(whole), got = blockKeys(blocks, index);
  EXPECT_EQ(got.vertices, expected.vertices);
  EXPECT_EQ(got.triangles, expected.triangles);
  EXPECT_EQ(boundaryEdges(got.triangles), boundaryEdges(expected.triangles));
  for (const BlockMesh& block : blocks)
    for (uint32_t i = 0; i < block.mesh.vertices.size(); ++i) {
      const int64_t at = index.find(blockPoint(block, i));
      ASSERT_GE(at, 0);
      EXPECT_EQ(block.mesh.labels[i], whole.labels[at]);
    }

  // Still the scene: the sphere's vertices (label 7) lie within a voxel of the 1 cm map of its
  // surface (centre (0, 0, 0.3), radius 0.25).
  std::size_t on_sphere = 0;
  for (const BlockMesh& block : blocks)
    for (uint32_t i = 0; i < block.own_vertices; ++i) {
      if (block.mesh.labels[i] != 7) continue;
      const Eigen::Vector3d p = blockPoint(block, i) * kVoxel * kStride;
      EXPECT_NEAR((p - Eigen::Vector3d(0, 0, 0.3)).norm(), 0.25, kVoxel) << p.transpose();
      ++on_sphere;
    }
  EXPECT_GT(on_sphere, 1000u);
}

// After a change, re-meshing blocksReadingLeaves(changed leaves, 2) at stride 2 gives the sampled
// mesh of the changed map: the coarse blocks that read a leaf are all found.
TEST_F(BlockMeshTest, RemeshingAtStrideTwoTheBlocksThatReadAChangedLeafGivesTheChangedMap) {
  constexpr int kStride = 2;
  volume::LabeledVolume changed = volume_->deepCopy();
  const std::vector<openvdb::Coord> leaves = allLeaves(changed);
  const std::vector<BlockMesh> before = extractBlockMeshes(changed, blocksReadingLeaves(leaves, kStride), kStride);
  std::vector<openvdb::Coord> pushed;
  for (std::size_t i = 0; i < leaves.size(); i += 7) pushed.push_back(leaves[i]);
  for (const openvdb::Coord& origin : pushed) {
    auto* leaf = changed.mutableGeometryGrid().tree().probeLeaf(origin);
    for (auto it = leaf->beginValueOn(); it; ++it) {
      const volume::VoxelValue v = volume::unpackVoxel(*it);
      it.setValue(volume::packVoxel(v.tsdf - 1.5f * static_cast<float>(kVoxel), v.weight, 3, v.score));
    }
  }
  std::map<openvdb::Coord, BlockMesh> blocks;
  for (const BlockMesh& b : before) blocks[b.origin] = b;
  for (BlockMesh& b : extractBlockMeshes(changed, blocksReadingLeaves(pushed, kStride), kStride))
    blocks[b.origin] = std::move(b);
  std::vector<BlockMesh> merged;
  for (auto& [origin, b] : blocks) merged.push_back(std::move(b));

  const LabeledMesh whole_before = extractMesh(sampledCopy(*volume_, kStride)).value();
  const LabeledMesh whole_after = extractMesh(sampledCopy(changed, kStride)).value();
  EXPECT_NE(whole_before.vertices, whole_after.vertices);
  const VertexIndex index(whole_after, kVoxel * kStride);
  const MeshKeys expected = wholeKeys(whole_after), got = blockKeys(merged, index);
  EXPECT_EQ(got.vertices, expected.vertices);
  EXPECT_EQ(got.triangles, expected.triangles);
}

// Against the definition: a block of stride s reads the map's voxels [s b, s b + 9 s] per axis.
TEST(BlocksReadingLeaves, AtEveryStrideExactlyTheBlocksWhoseVoxelsMeetTheLeaf) {
  for (int stride = 1; stride <= 8; ++stride)
    for (int leaf_x = -48; leaf_x <= 48; leaf_x += 8) {
      const openvdb::Coord leaf(leaf_x, 8, -16);
      const auto blocks = blocksReadingLeaves({leaf}, stride);
      std::set<openvdb::Coord> expected;
      for (int bx = -64; bx <= 64; bx += 8)
        for (int by = -64; by <= 64; by += 8)
          for (int bz = -64; bz <= 64; bz += 8) {
            auto meets = [stride](int b, int l) { return stride * b <= l + 7 && stride * b + 9 * stride >= l; };
            if (meets(bx, leaf.x()) && meets(by, leaf.y()) && meets(bz, leaf.z())) expected.emplace(bx, by, bz);
          }
      EXPECT_EQ(std::set<openvdb::Coord>(blocks.begin(), blocks.end()), expected)
          << "stride " << stride << " leaf " << leaf;
      EXPECT_TRUE(std::is_sorted(blocks.begin(), blocks.end()));
    }
}

TEST(BlocksReadingLeaves, EachLeafAndTheSevenBelowIt) {
  const auto blocks = blocksReadingLeaves({openvdb::Coord(8, 16, -8), openvdb::Coord(16, 16, -8)});
  // Two leaves side by side along x share the four blocks of the column between them.
  EXPECT_EQ(blocks.size(), 12u);
  EXPECT_TRUE(std::is_sorted(blocks.begin(), blocks.end()));
  for (const openvdb::Coord& b : blocks) {
    EXPECT_TRUE(b.x() == 0 || b.x() == 8 || b.x() == 16) << b;
    EXPECT_TRUE(b.y() == 8 || b.y() == 16) << b;
    EXPECT_TRUE(b.z() == -16 || b.z() == -8) << b;
  }
}

TEST(BlockMesh, UnallocatedOrEmptyBlocksHaveNoSurface) {
  volume::VolumeParams p;
  p.voxel_size = kVoxel;
  volume::LabeledVolume volume(p);
  // One leaf fully observed and outside (tsdf > 0): no crossing.
  auto& tree = volume.mutableGeometryGrid().tree();
  for (auto it = openvdb::CoordBBox({0, 0, 0}, {7, 7, 7}).begin(); it; ++it)
    tree.setValue(*it, volume::packVoxel(0.02f, 1.0f, 1, 1.0f));
  const auto blocks = extractBlockMeshes(volume, {openvdb::Coord(0, 0, 0), openvdb::Coord(64, 0, 0)});
  ASSERT_EQ(blocks.size(), 2u);
  EXPECT_EQ(blocks[1].origin, openvdb::Coord(64, 0, 0));
  for (const BlockMesh& b : blocks) {
    EXPECT_TRUE(b.mesh.vertices.empty());
    EXPECT_TRUE(b.mesh.triangles.empty());
    EXPECT_EQ(b.own_vertices, 0u);
  }
}

}  // namespace
}  // namespace semfuse::render
