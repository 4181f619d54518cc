// Fuzz target: the live mesh's messages, chosen by the first byte, serialized CDR after it:
//   0 MapUpdate_              wire::decodeMapUpdate, what a follower decodes from
//                             rt/semfuse/map_updates; an accepted update's blocks all validate and
//                             survive encode + decode unchanged
//   1 MapBlocks_Request_      the server's way: MapBlocksCodec::decodeRequest, handleMapBlocks on
//                             a small block store, encodeReply; a page keeps its byte bound
//   2 MapBlocks_Response_     MapBlocksCodec::decodeReply, what a follower decodes from map_blocks
// Other selector values are ignored.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "map_blocks_handler.hpp"
#include "mesh_block_store.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/map_update_codecs.hpp"

namespace {
using namespace semfuse;

// A block of one triangle at `origin`, meshed at `revision`.
MeshBlock triangleBlock(BlockOrigin origin, uint64_t revision) {
  MeshBlock block;
  block.origin = origin;
  block.revision = revision;
  block.own_vertices = 3;
  block.positions = {0, 0, 0, 4096, 0, 0, 0, 4096, 0};
  block.normals = {0, 0, 127, 0, 0, 127, 0, 0, 127};
  block.labels = {1, 1, 2};
  block.scores = {1.0F, 1.0F, 0.5F};
  block.triangles = {0, 1, 2};
  return block;
}

// Three blocks at revisions 1-3, one removed at revision 4; the mesh is at revision 5.
const server::MeshBlockStore& smallStore() {
  static const server::MeshBlockStore* store = [] {
    auto* s = new server::MeshBlockStore(42);
    s->apply({triangleBlock({0, 0, 0}, 1), triangleBlock({8, 0, 0}, 2), triangleBlock({0, 8, 0}, 3)});
    MeshBlock gone;
    gone.origin = {8, 0, 0};
    gone.revision = 4;
    s->apply({gone});
    s->setCurrent(5, 10, 0.02);
    return s;
  }();
  return *store;
}

void update(const uint8_t* data, size_t size) {
  auto sample = dds::deserialize<semfuse_msg_dds__MapUpdate_>(data, size);
  if (!sample) return;
  auto decoded = wire::decodeMapUpdate(*sample.value());
  if (!decoded) return;
  const MapUpdate& u = decoded.value();
  for (const MeshBlock& block : u.blocks) SEMFUSE_FUZZ_CHECK(wire::validateMeshBlock(block).ok());
  const wire::EncodedMapUpdate encoded = wire::encodeMapUpdate(u);
  auto again = wire::decodeMapUpdate(encoded.msg());
  SEMFUSE_FUZZ_CHECK(again.ok() && again.value().blocks.size() == u.blocks.size());
  for (std::size_t i = 0; i < u.blocks.size(); ++i) SEMFUSE_FUZZ_CHECK(again.value().blocks[i].sameMesh(u.blocks[i]));
}

void request(const uint8_t* data, size_t size) {
  auto sample = dds::deserialize<wire::MapBlocksCodec::WireRequest>(data, size);
  if (!sample) return;
  auto decoded = wire::MapBlocksCodec::decodeRequest(*sample.value());
  if (!decoded) return;
  constexpr uint32_t kPageBytes = 1024;
  const ServiceReply<MapBlocksPage> reply = server::handleMapBlocks(decoded.value(), &smallStore(), kPageBytes);
  SEMFUSE_FUZZ_CHECK(reply.ok() || !reply.message.empty());
  if (reply.ok()) {
    const std::size_t bound = decoded.value().max_bytes > 0 ? decoded.value().max_bytes : kPageBytes;
    std::size_t bytes = 0;
    for (const MeshBlock& block : reply.value.blocks) bytes += block.payloadBytes() + MeshBlock::kFramingBytes;
    SEMFUSE_FUZZ_CHECK(reply.value.blocks.size() <= 1 || bytes <= bound);
  }
  dds::Sample<wire::MapBlocksCodec::WireReply> wire_reply;
  wire::MapBlocksCodec::encodeReply(reply, *wire_reply);
  SEMFUSE_FUZZ_CHECK(wire_reply->status == static_cast<int32_t>(reply.code));
}

void page(const uint8_t* data, size_t size) {
  auto sample = dds::deserialize<wire::MapBlocksCodec::WireReply>(data, size);
  if (!sample) return;
  auto decoded = wire::MapBlocksCodec::decodeReply(*sample.value());
  if (!decoded || !decoded.value().ok()) return;
  for (const MeshBlock& block : decoded.value().value.blocks) SEMFUSE_FUZZ_CHECK(wire::validateMeshBlock(block).ok());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  if (selector == 0) update(data + 1, size - 1);
  if (selector == 1) request(data + 1, size - 1);
  if (selector == 2) page(data + 1, size - 1);
  return 0;
}
