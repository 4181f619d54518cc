#pragma once
// The map_blocks service as a plain function (like service_handlers.hpp): a page of the live
// mesh's blocks newer than a revision, for a follower that joins late or missed an update.
#include <cstdint>

#include "mesh_block_store.hpp"
#include "semfuse/core/map_blocks.hpp"
#include "semfuse/core/service_types.hpp"

namespace semfuse::server {

// store null: the server runs without the live mesh (--map-updates.rate 0): UNAVAILABLE.
ServiceReply<MapBlocksPage> handleMapBlocks(const MapBlocksRequest& request, const MeshBlockStore* store,
                                            uint32_t default_page_bytes);

}  // namespace semfuse::server
