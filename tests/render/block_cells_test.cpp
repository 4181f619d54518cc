// The block mesher's cell classification (block_cells.hpp) on hand-written planes whose cells
// are known: which cells carry a vertex, where a leaf above is missing, and that a block whose
// surface lies only in the layer of cells it shares with the block above has no mesh of its own.
#include <gtest/gtest.h>

#include "block_cells.hpp"
#include "semfuse/render/mesh_blocks.hpp"

namespace semfuse::render::detail {
namespace {

constexpr double kVoxel = 0.01;

// Observed voxels in `box`, on a horizontal plane at height `plane` (voxels): inside below it.
volume::LabeledVolume planeVolume(float plane, const openvdb::CoordBBox& box) {
  volume::VolumeParams p;
  p.voxel_size = kVoxel;
  p.integrate_color = false;
  volume::LabeledVolume volume(p);
  auto& tree = volume.mutableGeometryGrid().tree();
  for (auto it = box.begin(); it; ++it) {
    const float tsdf = (static_cast<float>((*it).z()) - plane) * static_cast<float>(kVoxel);
    tree.setValue(*it, volume::packVoxel(tsdf, 1.0f, 2, 0.5f));
  }
  return volume;
}

BlockCells classifyAt(const volume::LabeledVolume& volume, const openvdb::Coord& origin) {
  BlockVoxels voxels;
  EXPECT_TRUE(voxels.gather(volume.geometryGrid().getConstUnsafeAccessor(), origin));
  return classifyBlockCells(voxels);
}

// The block at the origin and all seven leaves above it observed.
const openvdb::CoordBBox kEightLeaves({0, 0, 0}, {15, 15, 15});

TEST(BlockCells, APlaneCrossesOneLayerOfCells) {
  const volume::LabeledVolume volume = planeVolume(4.5f, kEightLeaves);
  const BlockCells cells = classifyAt(volume, {0, 0, 0});
  for (int x = 0; x < kBlockCells; ++x)
    for (int y = 0; y < kBlockCells; ++y) {
      EXPECT_EQ(cells.surface[x][y], 1u << 4) << x << " " << y;  // corners z = 4 (inside) and 5
      EXPECT_EQ(cells.inside[x][y], 0x1Fu);                      // voxels z = 0..4
      EXPECT_EQ(cells.insideCorners(x, y, 4), 0x0Fu);            // the four lower corners
    }
  EXPECT_TRUE(cells.hasOwnSurface());
}

TEST(BlockCells, CellsReadingAMissingLeafCarryNoVertex) {
  // Only x < 8 is allocated: the cells at x = 7 and 8 have corners at x = 8, never observed.
  const volume::LabeledVolume volume = planeVolume(4.5f, openvdb::CoordBBox({0, 0, 0}, {7, 15, 15}));
  const BlockCells cells = classifyAt(volume, {0, 0, 0});
  for (int y = 0; y < kBlockCells; ++y) {
    EXPECT_EQ(cells.surface[6][y], 1u << 4);
    EXPECT_EQ(cells.surface[7][y], 0u);
    EXPECT_EQ(cells.surface[8][y], 0u);
    EXPECT_EQ(cells.inside[8][y], 0u);  // unobserved voxels are never inside
  }
}

TEST(BlockCells, SurfaceOnlyInTheSharedLayerBelongsToTheBlockAbove) {
  // The plane between voxel layers 8 and 9: only the cells at z = 8, which the block at the
  // origin shares with the block above, carry vertices.
  const volume::LabeledVolume volume = planeVolume(8.5f, openvdb::CoordBBox({0, 0, 0}, {15, 15, 23}));
  const BlockCells cells = classifyAt(volume, {0, 0, 0});
  for (int x = 0; x < kBlockCells; ++x)
    for (int y = 0; y < kBlockCells; ++y) EXPECT_EQ(cells.surface[x][y], 1u << 8);
  EXPECT_FALSE(cells.hasOwnSurface());

  const std::vector<BlockMesh> blocks = extractBlockMeshes(volume, {{0, 0, 0}, {0, 0, 8}});
  EXPECT_TRUE(blocks[0].mesh.vertices.empty());
  EXPECT_TRUE(blocks[0].mesh.triangles.empty());
  // The block above owns the 8 x 8 cells at its z = 0, and one quad per crossed z edge whose
  // lowest cell it owns: 8 x 8, those at x = 7 or y = 7 joining cells of the blocks at +x, +y.
  EXPECT_EQ(blocks[1].own_vertices, 64u);
  EXPECT_EQ(blocks[1].mesh.triangles.size(), 2u * 64u);
}

}  // namespace
}  // namespace semfuse::render::detail
