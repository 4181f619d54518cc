#include "distance_field.hpp"

#include <algorithm>
#include <iterator>

#include <spdlog/spdlog.h>

#include "semfuse/core/thread_name.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {
namespace {
constexpr std::size_t kCachedLabelSets = 8;
// Changed leaves applied per hold of the field's lock: tens of milliseconds at 1 cm.
constexpr std::size_t kLeavesPerHold = 256;
}  // namespace

namespace {
volume::VolumeParams mapParams(const Mapper& mapper) {
  return mapper.read([](const volume::LabeledVolume& map) { return map.params(); });
}
}  // namespace

DistanceField::DistanceField(const Mapper& mapper, esdf::EsdfParams params)
    : DistanceField(mapper, params, mapParams(mapper)) {}

DistanceField::DistanceField(const Mapper& mapper, esdf::EsdfParams params, const volume::VolumeParams& map)
    : mapper_(mapper),
      field_(params.fieldVoxel(map.voxel_size, map.truncation), params),
      stride_(params.stride(map.voxel_size, map.truncation)) {}

DistanceField::~DistanceField() { stop(); }

void DistanceField::start() {
  running_ = true;
  notify();  // a resumed map is there before any frame
  thread_ = std::thread([this] {
    setCurrentThreadName("sf-esdf");
    lowerToQueryPriority();
    nameTbbWorkers();
    run();
  });
}

void DistanceField::stop() {
  if (!running_.exchange(false)) return;
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DistanceField::notify() {
  {
    std::lock_guard lock(wake_mutex_);
    pending_ = true;
  }
  wake_.notify_all();
}

void DistanceField::run() {
  while (running_) {
    {
      std::unique_lock lock(wake_mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(200), [this] { return pending_ || !running_; });
      if (!running_) break;
      if (!pending_) continue;
      pending_ = false;
    }
    updateOnce();
    wake_.notify_all();  // waitUntilCurrent
  }
}

void DistanceField::updateOnce() {
  const auto start = std::chrono::steady_clock::now();
  const uint64_t since = revision_.load();
  // The copy is the only part that holds the map's lock.
  esdf::MapChanges changes = mapper_.read([&](const volume::LabeledVolume& map) {
    if (map.revision() == since) return esdf::MapChanges{since, false, field_.voxelSize(), {}};
    return esdf::copyChanges(map, since, stride_);
  });
  if (changes.revision == since && !changes.all) return;
  // The field's lock is taken per slice of the changed leaves, not for the whole update: at 1 cm a
  // field that fell behind under load needs seconds to apply what changed meanwhile, and a
  // distance query that waited out all of it got no reply within its timeout. Each slice is
  // applied as if the map had changed that much (the field reaches the same state once the last
  // slice is in); queries take the lock between slices, and stop() ends the update there.
  esdf::UpdateStats stats;
  // A rebuild (the map was cleared, replaced or is new) goes in one piece: sliced, it would show
  // queries an emptied field filling up.
  const std::size_t total = changes.leaves.size();
  const std::size_t per_hold = changes.all ? std::max<std::size_t>(total, 1) : kLeavesPerHold;
  for (std::size_t first = 0; first == 0 || first < total; first += per_hold) {
    if (first > 0 && !running_) return;  // stopping: the field stays at its last whole revision
    const std::size_t last = std::min(total, first + per_hold);
    esdf::MapChanges slice;
    slice.revision = last == total ? changes.revision : since;
    slice.all = first == 0 && changes.all;
    slice.voxel_size = changes.voxel_size;
    slice.leaves.assign(std::make_move_iterator(changes.leaves.begin() + static_cast<std::ptrdiff_t>(first)),
                        std::make_move_iterator(changes.leaves.begin() + static_cast<std::ptrdiff_t>(last)));
    std::unique_lock lock(mutex_);
    const esdf::UpdateStats part = field_.apply(slice);
    stats.leaves += part.leaves;
    stats.rebuilt = stats.rebuilt || part.rebuilt;
  }
  revision_ = changes.revision;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  last_update_ms_ = ms;
  ++updates_;
  if (timings_) timings_->record(Stage::kDistanceField, ms);
  if (stats.rebuilt) spdlog::info("distance field rebuilt: {} leaves in {:.0f} ms", stats.leaves, ms);
}

bool DistanceField::waitUntilCurrent(std::chrono::milliseconds timeout) const {
  const uint64_t target = mapper_.read([](const volume::LabeledVolume& map) { return map.revision(); });
  std::unique_lock lock(wake_mutex_);
  return wake_.wait_for(lock, timeout, [&] { return revision_.load() >= target && !pending_; });
}

std::shared_ptr<const esdf::SurfaceIndex> DistanceField::surfaceIndex(std::vector<LabelId> labels) const {
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const uint64_t surfaces_revision = readField([](const esdf::EsdfMap& f) { return f.surfaces().revision(); });
  {
    std::lock_guard lock(cache_mutex_);
    auto it = cache_.find(labels);
    if (it != cache_.end() && it->second.surfaces_revision == surfaces_revision) return it->second.index;
  }
  // Gather under the field's lock, build the tree without it.
  uint64_t gathered_at = 0;
  std::vector<esdf::SurfacePoint> points = readField([&](const esdf::EsdfMap& f) {
    gathered_at = f.surfaces().revision();
    return f.surfaces().gather(labels);
  });
  auto index = std::make_shared<const esdf::SurfaceIndex>(std::move(points));
  std::lock_guard lock(cache_mutex_);
  if (cache_.size() >= kCachedLabelSets && !cache_.count(labels)) cache_.erase(cache_.begin());
  cache_[labels] = {gathered_at, index};
  return index;
}

DistanceField::Stats DistanceField::stats() const {
  Stats s;
  s.updates = updates_.load();
  s.last_update_ms = last_update_ms_.load();
  s.revision = revision_.load();
  readField([&](const esdf::EsdfMap& f) {
    s.known_voxels = f.knownVoxels();
    s.memory_bytes = f.memoryBytes();
    return 0;
  });
  return s;
}

}  // namespace semfuse::server
