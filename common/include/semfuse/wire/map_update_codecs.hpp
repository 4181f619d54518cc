#pragma once
// The live mesh on the wire: MapUpdate <-> semfuse::msg::dds_::MapUpdate_ (topic
// rt/semfuse/map_updates) and the map_blocks service's codec (MapBlocksRequest / MapBlocksPage),
// with the same members as the codecs of service_codecs.hpp.
//
// A block that does not add up is refused with a message naming it: array lengths that do not
// match its vertex count (3 positions, 3 normals, 1 label, 1 score, 0 or 3 colour bytes per
// vertex), triangles not in threes or pointing past the vertices, more than 65536 vertices, more
// own vertices than vertices, an origin that is not a multiple of the block size.
#include <cstddef>

#include <msg.h>
#include <srv.h>

#include "semfuse/core/map_blocks.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/wire/owned_message.hpp"

namespace semfuse::wire {

using EncodedMapUpdate = OwnedMessage<semfuse_msg_dds__MapUpdate_>;

// The message points into `update`'s arrays instead of copying them (an update can hold
// megabytes): keep `update` alive and unchanged while the message is in use.
EncodedMapUpdate encodeMapUpdate(const MapUpdate& update);
Result<MapUpdate> decodeMapUpdate(const semfuse_msg_dds__MapUpdate_& msg);

Result<MeshBlock> decodeMeshBlock(const semfuse_msg_dds__MeshBlock_& msg);
// Checks a block's arrays against each other (the refusals listed above).
Status validateMeshBlock(const MeshBlock& block);

struct MapBlocksCodec {
  static constexpr const char* kName = "map_blocks";
  using Request = MapBlocksRequest;
  using Reply = MapBlocksPage;
  using WireRequest = semfuse_srv_dds__MapBlocks_Request_;
  using WireReply = semfuse_srv_dds__MapBlocks_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  // Every block is checked (validateMeshBlock).
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

}  // namespace semfuse::wire
