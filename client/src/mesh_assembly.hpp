#pragma once
// Puts the PLY of a chunked mesh reply back together. Private to the client library; the chunks
// themselves are decoded by common/wire (MeshCodec).
#include <cstddef>
#include <cstdint>

#include "semfuse/client/map_client.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/service_types.hpp"

namespace semfuse::client::detail {

// The most a mesh reply makes the client reserve before its bytes arrive (beyond it the PLY
// buffer grows with the chunks as they come).
inline constexpr uint64_t kMaxMeshReserveBytes = uint64_t{64} << 20;

// Chunk 0 names the mesh (id, chunk count, total bytes); every later chunk must come from that
// mesh, in order, and the bytes must add up to the announced total. Sizes in a reply are not
// trusted for allocations.
class MeshAssembly {
 public:
  // Reply `index` (0, 1, ... in order); an error says why it does not belong.
  Status add(MeshChunk chunk, uint32_t index);
  // Chunks announced by chunk 0 (1 before it arrived).
  uint32_t chunkCount() const { return chunk_count_; }
  uint64_t meshId() const { return mesh_id_; }
  // Bytes the PLY buffer holds room for (for tests: what a reply made the client allocate).
  std::size_t reservedBytes() const { return mesh_.ply.capacity(); }
  // The mesh, once every chunk was added; an error when bytes are missing.
  Result<MeshData> finish() &&;

 private:
  MeshData mesh_;
  uint64_t mesh_id_ = 0;
  uint32_t chunk_count_ = 1;
  uint32_t chunks_added_ = 0;
  uint64_t total_bytes_ = 0;
};

}  // namespace semfuse::client::detail
