#include "map_blocks_handler.hpp"

#include <string>

namespace semfuse::server {

ServiceReply<MapBlocksPage> handleMapBlocks(const MapBlocksRequest& request, const MeshBlockStore* store,
                                            uint32_t default_page_bytes) {
  if (store == nullptr)
    return ServiceReply<MapBlocksPage>::failure(ReplyCode::kUnavailable,
                                                "the server runs without map updates (--map-updates.rate 0)");
  const MapBlocksHeader header = store->header();
  if (request.since_revision > header.revision)
    return ServiceReply<MapBlocksPage>::failure(
        ReplyCode::kInvalidArgument, "since_revision " + std::to_string(request.since_revision) +
                                         " is ahead of the map's mesh (revision " + std::to_string(header.revision) +
                                         "): a follower of another server run starts over from 0");
  ServiceReply<MapBlocksPage> reply;
  reply.value = store->page(request, default_page_bytes);
  return reply;
}

}  // namespace semfuse::server
