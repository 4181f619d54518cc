#include "map_updater.hpp"

#include <random>
#include <utility>
#include <vector>

#include <spdlog/spdlog.h>

#include "mesh_block_encoding.hpp"
#include "semfuse/render/mesh_blocks.hpp"

namespace semfuse::server {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

int64_t nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

uint64_t newSession() {
  std::random_device device;
  const uint64_t session = (uint64_t{device()} << 32) | device();
  return session == 0 ? 1 : session;
}

// The system clock now, as a ROS time stamp.
Stamp stampNow() {
  const auto ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
  return {static_cast<int32_t>(ns / 1000000000), static_cast<uint32_t>(ns % 1000000000)};
}

std::size_t wireBytes(const MeshBlock& block) { return block.payloadBytes() + MeshBlock::kFramingBytes; }

}  // namespace

MapUpdater::MapUpdater(const MapAccess& map, const MapUpdateConfig& config, Sink& sink)
    : map_(map), config_(config), sink_(sink), store_(newSession()) {}

MapUpdater::~MapUpdater() { stop(); }

void MapUpdater::start() {
  if (!(config_.rate_hz > 0.0)) return;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.rate_hz));
  rounds_.start("sf-map-updates", period, [this] { update(); });
}

void MapUpdater::stop() { rounds_.stop(); }

void MapUpdater::touch() { touched_at_ns_ = nowNs(); }

bool MapUpdater::wanted() const {
  if (sink_.listening()) return true;
  const int64_t touched = touched_at_ns_.load();
  return touched != 0 && static_cast<double>(nowNs() - touched) * 1e-9 < config_.idle_after_s;
}

MapUpdater::Round MapUpdater::update() {
  Round round;
  const auto start = Clock::now();
  if (!wanted()) {
    round.skipped = true;
    std::lock_guard lock(totals_mutex_);
    ++totals_.rounds;
    ++totals_.skipped;
    return round;
  }

  const MapBlocksHeader before = store_.header();
  volume::LabeledVolume::LeafChanges changes;
  uint64_t frames = 0;
  double voxel_size = 0.0;
  int stride = 1;
  map_.read([&](const volume::LabeledVolume& volume) {
    changes = volume.changesSince(before.revision);
    frames = volume.framesIntegrated();
    stride = config_.stride(volume.voxelSize(), volume.params().truncation);
    voxel_size = volume.voxelSize() * stride;
  });

  // A clear or a replacing map: every block starts over. At the map's own resolution every block
  // with surface has a leaf of its own, so the changed leaves are the blocks.
  std::vector<openvdb::Coord> blocks;
  if (changes.all) store_.clear(changes.revision);
  if (changes.all && stride == 1) blocks = std::move(changes.leaves);
  else blocks = render::blocksReadingLeaves(changes.leaves, stride);

  std::vector<MeshBlock> changed;
  const std::size_t batch = std::max<std::size_t>(1, config_.batch_blocks);
  for (std::size_t first = 0; first < blocks.size(); first += batch) {
    const std::vector<openvdb::Coord> origins(
        blocks.begin() + static_cast<std::ptrdiff_t>(first),
        blocks.begin() + static_cast<std::ptrdiff_t>(std::min(first + batch, blocks.size())));
    // Only the copying of the blocks' voxels holds the map: the meshing, several times slower,
    // runs beside the fusion thread's next frame.
    render::GatheredBlocks gathered;
    uint64_t meshed_at = 0;
    const auto locked = Clock::now();
    map_.read([&](const volume::LabeledVolume& volume) {
      gathered = render::gatherBlocks(volume, origins, stride);
      meshed_at = volume.revision();
    });
    round.locked_ms += msSince(locked);
    std::vector<render::BlockMesh> meshes = render::meshGatheredBlocks(gathered);
    std::vector<MeshBlock> encoded;
    encoded.reserve(meshes.size());
    for (render::BlockMesh& mesh : meshes) encoded.push_back(encodeMeshBlock(std::move(mesh), meshed_at));
    for (MeshBlock& block : store_.apply(std::move(encoded))) changed.push_back(std::move(block));
  }
  round.blocks_meshed = blocks.size();
  round.blocks_sent = changed.size();
  store_.setCurrent(changes.revision, frames, voxel_size);

  uint64_t payload = 0;
  for (const MeshBlock& block : changed) payload += block.payloadBytes();
  if (!changed.empty() || changes.all) {
    round.parts = publishParts(std::move(changed), changes.all);
  }
  round.total_ms = msSince(start);
  if (timings_) timings_->record(Stage::kMapUpdate, round.total_ms);

  std::lock_guard lock(totals_mutex_);
  ++totals_.rounds;
  totals_.updates += round.parts > 0 ? 1 : 0;
  totals_.parts += round.parts;
  totals_.blocks_meshed += round.blocks_meshed;
  totals_.blocks_sent += round.blocks_sent;
  totals_.payload_bytes += payload;
  totals_.locked_ms += round.locked_ms;
  totals_.busy_ms += round.total_ms;
  return round;
}

// Cuts the blocks into parts of at most sample_bytes (at least one block each) and publishes
// them as one update; returns how many parts.
std::size_t MapUpdater::publishParts(std::vector<MeshBlock> blocks, bool cleared) {
  std::vector<std::vector<MeshBlock>> parts(1);
  std::size_t bytes = 0;
  for (MeshBlock& block : blocks) {
    const std::size_t size = wireBytes(block);
    if (!parts.back().empty() && bytes + size > config_.sample_bytes) {
      parts.emplace_back();
      bytes = 0;
    }
    bytes += size;
    parts.back().push_back(std::move(block));
  }
  MapUpdate update;
  update.header = store_.header();
  update.previous_revision = published_revision_;
  update.parts = static_cast<uint32_t>(parts.size());
  update.stamp = stampNow();
  for (std::size_t i = 0; i < parts.size(); ++i) {
    update.part = static_cast<uint32_t>(i);
    update.blocks = std::move(parts[i]);
    sink_.publish(update);
  }
  published_revision_ = update.header.revision;
  if (cleared) spdlog::debug("map updates: map cleared or replaced at revision {}", update.header.revision);
  return parts.size();
}

MapUpdater::Totals MapUpdater::totals() const {
  std::lock_guard lock(totals_mutex_);
  return totals_;
}

}  // namespace semfuse::server
