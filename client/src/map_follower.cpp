#include "semfuse/client/map_follower.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/wire/map_update_codecs.hpp"

namespace semfuse::client {

std::size_t MapFollowerState::vertexCount() const {
  std::size_t n = 0;
  for (const auto& [origin, block] : blocks) n += block.own_vertices;
  return n;
}

// The follower's bookkeeping, on its own thread:
//  - each block's newest revision, also of blocks that were removed (a catch-up page can carry
//    an older mesh of a block than an update already removed: it must not come back);
//  - covered: every change up to this revision is applied. An update whose previous revision is
//    newer than covered means one was missed: catch up since covered. An update's parts count
//    once all have come.
struct MapFollower::Impl {
  Impl(const dds::Participant& participant, Options opts)
      : options(opts),
        topic(participant, dds::topics::kMapUpdates),
        reader(topic, dds::qos::mapUpdates()),
        ready(reader.handle()),
        stop_guard(participant),
        waitset(participant),
        blocks_rpc(participant, dds::topics::mapBlocks()) {
    waitset.attach(ready.handle());
    waitset.attach(stop_guard.handle());
  }

  void run() {
    setCurrentThreadName("map-follower");
    // Everything there is, first; then updates, catching up whenever one was missed.
    bool need_catch_up = true;
    while (!stopping) {
      if (need_catch_up) need_catch_up = !catchUp();
      auto woke = waitset.wait(need_catch_up ? DDS_MSECS(500) : DDS_MSECS(200));
      if (!woke) spdlog::debug("map follower: {}", woke.error());
      if (stopping) break;
      while (auto sample = reader.take()) {
        auto update = wire::decodeMapUpdate(**sample);
        if (!update) {
          spdlog::warn("map follower: an update that does not decode: {}", update.error());
          std::lock_guard lock(mutex);
          ++stats.rejected;
          need_catch_up = true;
          continue;
        }
        if (!applyUpdate(update.value())) need_catch_up = true;
      }
    }
  }

  // Applies one update part; false when the follower is missing something and must catch up.
  bool applyUpdate(const MapUpdate& update) {
    std::unique_lock lock(mutex);
    MapFollowerChange change;
    change.source = MapFollowerChange::Source::kUpdate;
    const bool new_session = update.header.session != state.header.session;
    if (new_session) startOver(update.header.session, change);
    applyHeader(update.header, change);
    for (const MeshBlock& block : update.blocks) applyBlock(block, change);
    ++stats.updates;

    bool complete = !new_session;
    if (update.previous_revision > state.covered_revision) complete = false;  // one was missed
    if (complete) {
      if (update.header.revision != parts_revision) {
        // A new update: an earlier one that never got all its parts was missed.
        if (!parts_seen.empty()) complete = false;
        parts_revision = update.header.revision;
        parts_seen.clear();
      }
      parts_seen.insert(update.part);
      if (complete && parts_seen.size() == update.parts) {
        state.covered_revision = std::max(state.covered_revision, update.header.revision);
        parts_seen.clear();
      }
    }
    if (!complete) {
      ++stats.gaps;
      parts_seen.clear();
    }
    notify(change, lock);
    return complete;
  }

  // Pages of everything newer than covered; true once the last page is applied.
  bool catchUp() {
    // No server publishing updates (yet): nothing to ask, and a call would wait out its timeout.
    if (reader.matchedWriters() == 0) return false;
    uint64_t since;
    {
      std::lock_guard lock(mutex);
      since = state.covered_revision;
    }
    MapBlocksRequest request;
    request.since_revision = since;
    request.max_bytes = options.page_bytes;
    std::optional<uint64_t> first_revision;
    while (!stopping) {
      dds::Sample<wire::MapBlocksCodec::WireRequest> wire_request;
      wire::MapBlocksCodec::encodeRequest(request, *wire_request);
      auto wire_reply = blocks_rpc.call(*wire_request, options.request_timeout);
      if (!wire_reply) {
        spdlog::debug("map follower: map_blocks: {}", wire_reply.error());
        std::lock_guard lock(mutex);
        ++stats.failed_calls;
        return false;
      }
      auto reply = wire::MapBlocksCodec::decodeReply(*wire_reply.value());
      if (!reply || !reply.value().ok()) {
        const std::string why = !reply ? reply.error() : reply.value().message;
        spdlog::warn("map follower: map_blocks: {}", why);
        std::lock_guard lock(mutex);
        ++(!reply ? stats.rejected : stats.failed_calls);
        // A revision ahead of the server's mesh: another server run; start over from nothing.
        if (reply && reply.value().code == ReplyCode::kInvalidArgument) state.covered_revision = 0;
        return false;
      }
      const MapBlocksPage& page = reply.value().value;
      std::unique_lock lock(mutex);
      MapFollowerChange change;
      change.source = MapFollowerChange::Source::kCatchUp;
      if (page.header.session != state.header.session) {
        // Another server run than the follower knew: all over again. A follower that asked for
        // everything can take this very page.
        const bool from_scratch = since == 0 && !request.resume_after;
        startOver(page.header.session, change);
        if (!from_scratch) {
          notify(change, lock);
          return false;
        }
      }
      if (!first_revision) first_revision = page.header.revision;
      applyHeader(page.header, change);
      for (const MeshBlock& block : page.blocks) applyBlock(block, change);
      ++stats.pages;
      if (page.complete) {
        // Everything up to the first page's revision is in; later changes came in the pages or
        // come in updates.
        state.covered_revision = std::max(state.covered_revision, *first_revision);
        ++stats.catch_ups;
        notify(change, lock);
        return true;
      }
      notify(change, lock);
      request.resume_after = page.next_after;
    }
    return false;
  }

  void startOver(uint64_t session, MapFollowerChange& change) {
    state = MapFollowerState{};
    state.header.session = session;
    revisions.clear();
    parts_revision = 0;
    parts_seen.clear();
    change.started_over = true;
  }

  // A newer clear drops every block older than it.
  void applyHeader(const MapBlocksHeader& header, MapFollowerChange& change) {
    if (header.cleared_revision > state.header.cleared_revision) {
      for (auto it = state.blocks.begin(); it != state.blocks.end();) {
        if (it->second.revision < header.cleared_revision) {
          change.removed.push_back(it->first);
          it = state.blocks.erase(it);
        } else {
          ++it;
        }
      }
      for (auto it = revisions.begin(); it != revisions.end();)
        it = it->second < header.cleared_revision ? revisions.erase(it) : std::next(it);
    }
    const uint64_t cleared = std::max(state.header.cleared_revision, header.cleared_revision);
    if (header.revision >= state.header.revision) state.header = header;
    state.header.cleared_revision = cleared;
  }

  void applyBlock(const MeshBlock& block, MapFollowerChange& change) {
    if (block.revision < state.header.cleared_revision) return;  // from before a clear
    uint64_t& newest = revisions[block.origin];
    if (block.revision < newest) return;  // an older mesh than the one applied
    newest = block.revision;
    if (block.empty()) {
      if (state.blocks.erase(block.origin) > 0) change.removed.push_back(block.origin);
      return;
    }
    MeshBlock& kept = state.blocks[block.origin];
    kept = block;
    change.changed.push_back(&kept);
  }

  void notify(MapFollowerChange& change, std::unique_lock<std::mutex>& lock) {
    change.state = &state;
    // A block changed twice in one batch is listed once, by its final address.
    std::sort(change.changed.begin(), change.changed.end());
    change.changed.erase(std::unique(change.changed.begin(), change.changed.end()), change.changed.end());
    if (listener && (change.started_over || !change.removed.empty() || !change.changed.empty())) listener(change);
    lock.unlock();
    changed.notify_all();
  }

  Options options;
  dds::Topic<semfuse_msg_dds__MapUpdate_> topic;
  dds::Reader<semfuse_msg_dds__MapUpdate_> reader;
  dds::ReadCondition ready;
  dds::GuardCondition stop_guard;
  dds::WaitSet waitset;
  dds::RpcClient<wire::MapBlocksCodec::WireRequest, wire::MapBlocksCodec::WireReply> blocks_rpc;
  Listener listener;

  mutable std::mutex mutex;  // guards the members below
  mutable std::condition_variable changed;
  MapFollowerState state;
  std::map<BlockOrigin, uint64_t> revisions;
  uint64_t parts_revision = 0;
  std::set<uint32_t> parts_seen;
  MapFollowerStats stats;

  std::atomic<bool> stopping{false};
  std::thread thread;
};

MapFollower::MapFollower(const dds::Participant& participant) : MapFollower(participant, Options{}) {}
MapFollower::MapFollower(const dds::Participant& participant, Options options)
    : impl_(std::make_unique<Impl>(participant, options)) {}
MapFollower::~MapFollower() { stop(); }

void MapFollower::setListener(Listener listener) { impl_->listener = std::move(listener); }

void MapFollower::start() {
  if (impl_->thread.joinable()) return;
  impl_->stopping = false;
  impl_->thread = std::thread([this] { impl_->run(); });
}

void MapFollower::stop() {
  impl_->stopping = true;
  impl_->stop_guard.trigger();
  if (impl_->thread.joinable()) impl_->thread.join();
  impl_->stop_guard.reset();
}

void MapFollower::visit(const std::function<void(const MapFollowerState&)>& fn) const {
  std::lock_guard lock(impl_->mutex);
  fn(impl_->state);
}

bool MapFollower::waitFor(const std::function<bool(const MapFollowerState&)>& done,
                          std::chrono::milliseconds timeout) const {
  std::unique_lock lock(impl_->mutex);
  return impl_->changed.wait_for(lock, timeout, [&] { return done(impl_->state); });
}

MapFollowerStats MapFollower::stats() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->stats;
}

}  // namespace semfuse::client
