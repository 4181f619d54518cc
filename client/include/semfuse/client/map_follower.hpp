#pragma once
// MapFollower: the server's live mesh, block by block, kept up to date on a thread of its own.
// It reads rt/semfuse/map_updates and asks the map_blocks service for what it lacks: everything
// when it starts (or the server restarted), and what changed since the last update it had
// whenever it missed one (a sample lost or overwritten, a part of an update missing). Each block
// it keeps is the newest mesh the server published for it; blocks whose surface went away, and
// all blocks when the map was cleared or replaced, are dropped.
//
//   semfuse::dds::Participant participant;
//   semfuse::client::MapFollower follower(participant);
//   follower.setListener([](const semfuse::client::MapFollowerChange& change) {
//     for (const semfuse::MeshBlock* block : change.changed) draw(*block);  // on the follower's thread
//   });
//   follower.start();
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "semfuse/core/map_blocks.hpp"
#include "semfuse/dds/participant.hpp"

namespace semfuse::client {

// The mesh as the follower holds it.
struct MapFollowerState {
  MapBlocksHeader header;                   // of the newest update or page applied (session, voxel size, frames)
  uint64_t covered_revision = 0;            // every change of the map up to this revision is applied
  std::map<BlockOrigin, MeshBlock> blocks;  // the blocks with surface

  std::size_t vertexCount() const;  // own vertices of all blocks: each surface vertex once
};

// What one update or one catch-up page changed, for the listener.
struct MapFollowerChange {
  enum class Source { kUpdate, kCatchUp };
  Source source = Source::kUpdate;
  bool started_over = false;                // every block was dropped first (new server run, or a clear)
  std::vector<BlockOrigin> removed;         // blocks dropped (beside a start over)
  std::vector<const MeshBlock*> changed;    // blocks added or replaced; valid during the call
  const MapFollowerState* state = nullptr;  // after the change
};

struct MapFollowerStats {
  uint64_t updates = 0;       // update samples applied
  uint64_t gaps = 0;          // updates found missing (each followed by a catch-up)
  uint64_t catch_ups = 0;     // catch-ups completed
  uint64_t pages = 0;         // map_blocks replies applied
  uint64_t rejected = 0;      // samples or replies that did not decode (counted, then caught up)
  uint64_t failed_calls = 0;  // map_blocks calls that failed (retried)
};

class MapFollower {
 public:
  struct Options {
    std::chrono::milliseconds request_timeout{10000};  // per map_blocks page
    uint32_t page_bytes = 0;                           // 0 = the server's
  };
  using Listener = std::function<void(const MapFollowerChange&)>;

  explicit MapFollower(const dds::Participant& participant);
  MapFollower(const dds::Participant& participant, Options options);
  ~MapFollower();  // stops
  MapFollower(const MapFollower&) = delete;
  MapFollower& operator=(const MapFollower&) = delete;

  // Called on the follower's thread after each change, under the follower's lock (visit() waits
  // meanwhile). Set before start().
  void setListener(Listener listener);
  void start();
  void stop();

  // Calls fn with the state under the follower's lock: the listener is not called meanwhile, so
  // a copy taken here plus the changes the listener sees afterwards is the whole mesh.
  void visit(const std::function<void(const MapFollowerState&)>& fn) const;
  // Waits up to `timeout` until done(state) holds (checked after each change); false on timeout.
  bool waitFor(const std::function<bool(const MapFollowerState&)>& done, std::chrono::milliseconds timeout) const;
  MapFollowerStats stats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace semfuse::client
