#pragma once
// MeshBlockStore: the current mesh of every block of the map, as the map updates published it,
// and the header that says how far it is up to date. The map update thread writes it; the
// map_blocks service reads pages of it for followers that join late or missed an update.
// Thread-safe. A block whose surface went away stays as an empty block with the revision of its
// removal, so that a follower asking for what changed since an older revision hears of it; a
// clear forgets everything.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <vector>

#include "semfuse/core/map_blocks.hpp"

namespace semfuse::server {

class MeshBlockStore {
 public:
  // `session` names this server run on the wire (MapBlocksHeader::session).
  explicit MeshBlockStore(uint64_t session);

  // Takes meshed blocks (each with the map revision it was meshed at) and returns those whose
  // mesh differs from the stored one: new blocks with surface, changed ones, and stored ones that
  // became empty. Unchanged blocks keep their old revision; empty blocks never stored are dropped.
  std::vector<MeshBlock> apply(std::vector<MeshBlock> blocks);
  // The map was cleared or replaced at `revision`: every block is gone.
  void clear(uint64_t revision);
  // Everything that changed up to `revision` is stored.
  void setCurrent(uint64_t revision, uint64_t frames_integrated, double voxel_size);

  MapBlocksHeader header() const;
  // The blocks newer than request.since_revision after request.resume_after, in origin order, up
  // to max_bytes of wire size (request.max_bytes, else default_bytes; at least one block). Empty
  // blocks are left out when since_revision is 0 (a new follower has nothing to remove).
  MapBlocksPage page(const MapBlocksRequest& request, uint32_t default_bytes) const;
  // Calls fn with every block that has surface, in origin order, under the store's lock.
  void visitBlocks(const std::function<void(const std::vector<const MeshBlock*>&)>& fn) const;

  struct Totals {
    std::size_t blocks = 0;  // with surface
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::size_t payload_bytes = 0;
  };
  Totals totals() const;

 private:
  mutable std::mutex mutex_;
  MapBlocksHeader header_;
  std::map<BlockOrigin, MeshBlock> blocks_;
};

}  // namespace semfuse::server
