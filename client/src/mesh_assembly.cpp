#include "mesh_assembly.hpp"

#include <algorithm>
#include <string>
#include <utility>

namespace semfuse::client::detail {

Status MeshAssembly::add(MeshChunk chunk, uint32_t index) {
  if (index != chunks_added_)
    return makeError("mesh chunk " + std::to_string(index) + " added after " + std::to_string(chunks_added_) +
                     " chunks (they go in order)");
  if (index == 0) {
    // The first reply names the mesh that later chunks must come from.
    mesh_id_ = chunk.mesh_id;
    chunk_count_ = std::max<uint32_t>(1, chunk.chunk_count);
    total_bytes_ = chunk.total_bytes;
    mesh_.vertex_count = chunk.vertex_count;
    mesh_.face_count = chunk.face_count;
    // Reserve what was announced, up to what can be trusted before the bytes arrive: the server
    // cuts equal chunks but the last (so never more than chunk_count x the first), and a count
    // near 2^32 with a total to match must not make the client allocate gigabytes up front.
    const uint64_t possible = static_cast<uint64_t>(chunk_count_) * chunk.ply.size();
    mesh_.ply.reserve(static_cast<std::size_t>(std::min({total_bytes_, possible, kMaxMeshReserveBytes})));
  } else if (index >= chunk_count_) {
    return makeError("mesh chunk " + std::to_string(index) + " beyond the " + std::to_string(chunk_count_) +
                     " chunks announced");
  } else if (chunk.mesh_id != mesh_id_ || chunk.chunk_index != index) {
    return makeError("mesh reply for chunk " + std::to_string(chunk.chunk_index) + " of mesh " +
                     std::to_string(chunk.mesh_id) + ", expected chunk " + std::to_string(index) + " of mesh " +
                     std::to_string(mesh_id_));
  }
  if (total_bytes_ != 0 && mesh_.ply.size() + chunk.ply.size() > total_bytes_)
    return makeError("mesh chunks hold more than the " + std::to_string(total_bytes_) + " bytes announced");
  if (chunk_count_ == 1) {
    mesh_.ply = std::move(chunk.ply);  // the whole mesh in one reply: nothing to join
  } else {
    mesh_.ply.insert(mesh_.ply.end(), chunk.ply.begin(), chunk.ply.end());
  }
  ++chunks_added_;
  return Status::Ok();
}

Result<MeshData> MeshAssembly::finish() && {
  if (chunks_added_ != chunk_count_)
    return makeError("mesh has " + std::to_string(chunks_added_) + " of " + std::to_string(chunk_count_) + " chunks");
  if (total_bytes_ != 0 && mesh_.ply.size() != total_bytes_)
    return makeError("mesh has " + std::to_string(mesh_.ply.size()) + " bytes, server announced " +
                     std::to_string(total_bytes_));
  return std::move(mesh_);
}

}  // namespace semfuse::client::detail
