#pragma once
// The live mesh of the map as plain C++ values: a MeshBlock is the labeled mesh of one block of
// the map (a leaf of 8^3 voxels), a MapUpdate the blocks that changed since the previous update
// (topic rt/semfuse/map_updates), MapBlocksRequest / MapBlocksPage the map_blocks service that
// gives a late or lagging follower the blocks it lacks. The server fills them, common/wire
// turns them into the generated types of idl/semfuse and back, the client library follows them.
//
// The arrays are what travels on the wire: positions in 1/4096 of a voxel from the block's
// origin (a block's vertices lie within 9 voxels of it), normals as int8 (x 127), one label and
// score per vertex, colours as RGB bytes, triangles as indices into the block's own vertices.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// A block's origin: the voxel index of its lowest corner voxel, each a multiple of kBlockVoxels.
using BlockOrigin = std::array<int32_t, 3>;

struct MeshBlock {
  static constexpr int kBlockVoxels = 8;            // voxels per block side (one volume leaf)
  static constexpr float kPositionScale = 4096.0F;  // position units per voxel

  BlockOrigin origin{};
  uint64_t revision = 0;  // map revision of this mesh: a newer one of the same block replaces it
  // Vertices [0, own_vertices) belong to the block's own cells; the others repeat vertices of
  // the blocks above it (+x, +y, +z) that its triangles reach. Count the own ones.
  uint32_t own_vertices = 0;
  std::vector<uint16_t> positions;  // 3 per vertex
  std::vector<int8_t> normals;      // 3 per vertex, towards free space
  std::vector<LabelId> labels;      // 1 per vertex
  std::vector<float> scores;        // 1 per vertex: the label's evidence
  std::vector<uint8_t> colors;      // 3 per vertex (RGB); empty without colour
  std::vector<uint16_t> triangles;  // 3 per triangle, counter-clockwise seen from free space

  std::size_t vertexCount() const { return labels.size(); }
  std::size_t triangleCount() const { return triangles.size() / 3; }
  // No vertices: the block's surface is gone.
  bool empty() const { return labels.empty(); }
  // Vertex i in the world frame, metres.
  Eigen::Vector3f position(std::size_t i, double voxel_size) const {
    const auto voxel = static_cast<float>(voxel_size);
    return {(static_cast<float>(origin[0]) + static_cast<float>(positions[3 * i]) / kPositionScale) * voxel,
            (static_cast<float>(origin[1]) + static_cast<float>(positions[3 * i + 1]) / kPositionScale) * voxel,
            (static_cast<float>(origin[2]) + static_cast<float>(positions[3 * i + 2]) / kPositionScale) * voxel};
  }
  // What a block adds to a CDR sample at most besides its arrays: origin, revision, vertex
  // count, six sequence lengths and their alignment.
  static constexpr std::size_t kFramingBytes = 72;
  // The bytes its arrays take; with kFramingBytes, what a block costs on the wire.
  std::size_t payloadBytes() const {
    return positions.size() * 2 + normals.size() + labels.size() * 2 + scores.size() * 4 + colors.size() +
           triangles.size() * 2;
  }
  // Same surface (everything but the revision).
  bool sameMesh(const MeshBlock& other) const {
    return own_vertices == other.own_vertices && positions == other.positions && normals == other.normals &&
           labels == other.labels && scores == other.scores && colors == other.colors && triangles == other.triangles;
  }
};

// What a follower needs to place blocks in time and space; shared by updates and pages.
struct MapBlocksHeader {
  uint64_t session = 0;            // random per server run: when it changes, a follower starts over
  uint64_t revision = 0;           // map revision the blocks bring a follower up to
  uint64_t cleared_revision = 0;   // the map was cleared or replaced then: older blocks are gone
  uint64_t frames_integrated = 0;  // frames in the map at `revision`
  double voxel_size = 0.0;
};

// rt/semfuse/map_updates: the blocks whose mesh changed since the previous update, in parts when
// they do not fit one sample. Empty blocks say their surface is gone.
struct MapUpdate {
  MapBlocksHeader header;
  uint64_t previous_revision = 0;  // revision of the update before this one (0 = none)
  uint32_t part = 0;
  uint32_t parts = 1;
  Stamp stamp;  // when it was published
  std::vector<MeshBlock> blocks;
};

// map_blocks: the blocks whose revision is newer than since_revision, a page at a time.
struct MapBlocksRequest {
  uint64_t since_revision = 0;              // 0 = every block
  std::optional<BlockOrigin> resume_after;  // the previous page's next_after
  uint32_t max_bytes = 0;                   // bound of the page's blocks (0 = the server's)
};
struct MapBlocksPage {
  MapBlocksHeader header;
  std::vector<MeshBlock> blocks;  // by origin
  bool complete = true;           // false: ask again with resume_after = next_after
  BlockOrigin next_after{};
};

}  // namespace semfuse
