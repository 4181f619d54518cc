#pragma once
// The map's surface block by block, for live views that follow the map as it grows: a block is
// one leaf of the volume (8^3 voxels), and its mesh can be made again alone when the leaves it
// reads change, so that the cost follows the change, not the map.
//
// The block owns the surface nets vertices of its 512 cells (a cell is named by its lowest corner
// voxel) and the quads of the crossed voxel edges whose lowest surrounding cell is one of them.
// Those quads reach one layer of cells into the blocks above (+x, +y, +z): the block repeats
// their vertices after its own, so that it can be drawn alone, and neighbouring blocks meet at
// identical vertices. Together the blocks give exactly the triangles of extractMesh's surface
// nets. A block reads the voxels [origin, origin + 10)^3: its own leaf and two layers of the seven
// leaves above it.
//
// A live view of a fine map can follow a coarser lattice: at stride s, block voxel (x, y, z) is the
// map's voxel s * (x, y, z), so that a block covers s^3 of the map's leaves and carries about 1/s^2
// of their vertices (the surface nets of the map's TSDF sampled every s voxels; the truncation
// band must be wider than s voxels for no surface to fall between samples). Block origins and
// vertices are then in the lattice's voxels, of s times the map's voxel size.
#include <cstdint>
#include <memory>
#include <vector>

#include <openvdb/openvdb.h>

#include "semfuse/render/mesh.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render {

struct BlockMesh {
  openvdb::Coord origin;  // the block's lowest voxel, in the block lattice (a multiple of 8)
  // Vertices in voxels from `origin` (world = (origin + vertex) * voxel size); the block's own
  // vertices first, then the repeated ones of the blocks above.
  LabeledMesh mesh;
  uint32_t own_vertices = 0;
};

// The blocks (of the lattice of `stride` map voxels, 1 to 8) whose mesh reads voxels of these map
// leaves (leaf origins): at stride 1 each leaf's own block and the seven below it (-x, -y, -z and
// their combinations). Sorted, without repeats.
std::vector<openvdb::Coord> blocksReadingLeaves(const std::vector<openvdb::Coord>& leaf_origins, int stride = 1);

// The mesh of each block in `origins` (block origins of the lattice of `stride` map voxels), in
// that order, in parallel. A block with none of the map's leaves under its own voxels allocated,
// or without surface, has an empty mesh. Reads the volume only: callers that share the volume
// with a writer hold its shared lock.
std::vector<BlockMesh> extractBlockMeshes(const volume::LabeledVolume& volume,
                                          const std::vector<openvdb::Coord>& origins, int stride = 1);

// The same in two steps, for a caller that shares the map with a writer: gatherBlocks copies out
// the voxels of the blocks with surface (under the map's shared lock, several times faster than
// meshing them), meshGatheredBlocks meshes the copies without the map.
class GatheredBlocks {
 public:
  GatheredBlocks();
  GatheredBlocks(GatheredBlocks&&) noexcept;
  GatheredBlocks& operator=(GatheredBlocks&&) noexcept;
  ~GatheredBlocks();
  std::size_t size() const;         // blocks asked for
  std::size_t withSurface() const;  // of them, those with surface (copied)

 private:
  struct Block;
  friend GatheredBlocks gatherBlocks(const volume::LabeledVolume&, const std::vector<openvdb::Coord>&, int);
  friend std::vector<BlockMesh> meshGatheredBlocks(const GatheredBlocks&);
  std::vector<openvdb::Coord> origins_;
  std::vector<std::unique_ptr<Block>> blocks_;  // null: no surface
  float voxel_size_ = 0;                        // of the lattice
  bool with_colors_ = false;
};
GatheredBlocks gatherBlocks(const volume::LabeledVolume& volume, const std::vector<openvdb::Coord>& origins,
                            int stride = 1);
std::vector<BlockMesh> meshGatheredBlocks(const GatheredBlocks& gathered);

}  // namespace semfuse::render
