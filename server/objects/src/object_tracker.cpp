#include "semfuse/objects/object_tracker.hpp"

#include <chrono>
#include <utility>

#include <tbb/parallel_for.h>

#include "semfuse/objects/grouping.hpp"
#include "semfuse/objects/surface_voxels.hpp"

namespace semfuse::objects {
namespace {

constexpr double kMinFloorArea = 0.25;      // m^2
constexpr double kMinFloorAgreement = 0.7;  // length of the mean unit normal

Stamp now() {
  const auto since_epoch = std::chrono::system_clock::now().time_since_epoch();
  const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(since_epoch).count();
  return {static_cast<int32_t>(ns / 1000000000), static_cast<uint32_t>(ns % 1000000000)};
}

}  // namespace

const TrackedObject* ObjectSet::find(uint32_t id) const {
  for (const TrackedObject& object : objects)
    if (object.id == id) return &object;
  return nullptr;
}

std::optional<Eigen::Vector3d> upFromFloor(const SurfaceVoxels& surface, const LabelLegend& legend) {
  std::vector<bool> floor(legend.maxId() + 1, false);
  bool any = false;
  for (const LabelInfo& info : legend.labels)
    if (info.name == "floor") floor[info.id] = any = true;
  if (!any) return std::nullopt;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double area = 0.0;
  for (const SurfaceVoxel& voxel : surface.voxels()) {
    if (voxel.label >= floor.size() || !floor[voxel.label]) continue;
    sum += voxel.area_m2 * voxel.normal.cast<double>();
    area += voxel.area_m2;
  }
  if (area < kMinFloorArea || sum.norm() < kMinFloorAgreement * area) return std::nullopt;
  return sum.normalized();
}

ObjectTracker::ObjectTracker(ObjectParams params, LabelLegend legend, double voxel_size)
    : params_(std::move(params)),
      legend_(std::move(legend)),
      views_(voxel_size),
      surface_cache_(legend_, params_.min_instance_evidence) {}

void ObjectTracker::setListener(std::function<void(const ObjectEvents&)> listener) {
  std::lock_guard lock(mutex_);
  listener_ = std::move(listener);
}

void ObjectTracker::recordView(const Frame& frame, const Pose& camera_to_world, float min_depth, float max_depth) {
  views_.record(frame.camera_id, frame.seq, frame.depth, frame.intrinsics, camera_to_world, min_depth, max_depth);
}

std::shared_ptr<const ObjectSet> ObjectTracker::objectsOf(const std::shared_ptr<const volume::LabeledVolume>& map) {
  const auto called_at = std::chrono::steady_clock::now();
  std::lock_guard lock(mutex_);
  return update(map, called_at);
}

std::shared_ptr<const ObjectSet> ObjectTracker::recentOrOf(
    std::chrono::duration<double> max_age, const std::function<std::shared_ptr<const volume::LabeledVolume>()>& map) {
  std::lock_guard lock(mutex_);
  // The update this call waited for may have been recent enough.
  const auto now = std::chrono::steady_clock::now();
  if (const Latest recent = latest(); recent.set && now - recent.current_at <= max_age) return recent.set;
  return update(map(), now);
}

std::shared_ptr<const ObjectSet> ObjectTracker::update(const std::shared_ptr<const volume::LabeledVolume>& map,
                                                       std::chrono::steady_clock::time_point called_at) {
  const auto publish = [&](std::shared_ptr<const ObjectSet> set) {
    std::lock_guard latest_lock(latest_mutex_);
    latest_ = {set, called_at};
    return set;
  };
  const bool same_map =
      last_ && !last_map_.owner_before(map) && !map.owner_before(last_map_) && last_revision_ == map->revision();
  // The view is recorded just after the frame's integration, so a call in between has the map
  // with the frame but not the frame among those that saw it: such a set gets its frames again.
  const uint64_t views = views_.version();
  if (same_map && views == last_views_) return publish(last_);
  if (same_map) {
    auto refreshed = std::make_shared<ObjectSet>(*last_);
    for (TrackedObject& object : refreshed->objects)
      object.frames = views_.framesSeeing(object.figures.leaves, kFramesPerObject, object.frame_count);
    last_ = refreshed;
    last_views_ = views;
    return publish(last_);
  }

  using Clock = std::chrono::steady_clock;
  const auto msSince = [](Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  };
  auto start = Clock::now();
  const SurfaceVoxels surface = surface_cache_.update(*map);
  last_times_.surface = msSince(start);
  start = Clock::now();
  ObjectParams params = params_;
  if (params.up_from_floor)
    if (auto up = upFromFloor(surface, legend_)) params.up = *up;
  const Grouping grouping = groupSurface(surface, params);
  last_times_.grouping = msSince(start);
  start = Clock::now();
  const ObjectRegistry::Assignment assignment = registry_.assign(surface, grouping);
  last_times_.ids = msSince(start);
  start = Clock::now();
  std::vector<ObjectFigures> figures = measureGroups(surface, grouping, params.up);

  auto set = std::make_shared<ObjectSet>();
  set->ids = assignment.id_tree;
  set->up = params.up;
  set->objects.resize(grouping.groups.size());
  tbb::parallel_for(std::size_t{0}, grouping.groups.size(), [&](std::size_t g) {
    TrackedObject& object = set->objects[g];
    const Group& group = grouping.groups[g];
    object.id = assignment.ids[g];
    object.label = group.label;
    object.fragment = group.fragment;
    object.instance = group.instance;
    object.figures = std::move(figures[g]);
    object.frames = views_.framesSeeing(object.figures.leaves, kFramesPerObject, object.frame_count);
  });
  if (!assignment.events.empty()) {
    ObjectEvents events;
    events.update = ++updates_;
    events.stamp = now();
    for (const Group& group : grouping.groups) events.object_count += group.fragment ? 0 : 1;
    events.events = assignment.events;
    if (listener_) listener_(events);
  }
  set->update = updates_;
  set->voxel_size = map->voxelSize();
  last_times_.figures = msSince(start);
  last_ = set;
  last_map_ = map;
  last_revision_ = map->revision();
  last_views_ = views;
  return publish(set);
}

}  // namespace semfuse::objects
