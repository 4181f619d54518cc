// semfuse-bench objects: the time of one objects query (labeled surface, grouping, ids, figures:
// what the server's objects service does on a new snapshot) on the synthetic room fused with its
// ground-truth labels, or on a saved map (--map: a server's map file, e.g. the 7-Scenes demo's,
// with its own legend) (target: <= 100 ms). The map is built or loaded once, untimed. Two queries
// are timed, each on a fresh copy of the map: the first of a tracker (every leaf's surface
// scanned), and one after part of the map changed (a contiguous --changed share of its leaves,
// in tree order, marked written since the last query, as a stretch of frames marks what they
// integrated: those leaves and their neighbours are re-scanned, the rest of the surface comes
// from the tracker's cache; grouping, ids and figures are redone whole). The surface extraction
// alone, timed in the same run, is the floor under the first query's cost. --picture draws the
// objects of the map from a given pose (objects/objects_picture.hpp).
#include <cstdio>
#include <memory>
#include <string>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "objects/objects_picture.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/objects/object_tracker.hpp"
#include "semfuse/objects/surface_voxels.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::bench {
namespace {

struct ObjectsBenchOptions {
  std::string map;  // a saved map instead of the synthetic room
  int frames = 300;
  double scale = 0.5;  // of the 640x480 camera
  double voxel = 0.02;
  std::size_t repeats = 10;
  double changed = 0.1;       // share of the leaves written between two queries
  std::string picture;        // PNG of the objects, from picture_pose
  std::string picture_pose;   // 4x4 camera-to-world matrix file; empty: looking at the map from above its box
  double picture_back = 0.0;  // metres the picture's camera is moved back along its optical axis
};

// Where the picture is taken from without a pose file: above the map's box, two thirds of its
// diagonal away, looking down at its centre at 60 degrees.
Pose overviewPose(const volume::LabeledVolume& map, const Eigen::Vector3d& up_hint) {
  openvdb::CoordBBox box = map.geometryGrid().evalActiveVoxelBoundingBox();
  const Eigen::Vector3d lo = map.indexToWorld(box.min()), hi = map.indexToWorld(box.max());
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const Eigen::Vector3d up = up_hint.norm() > 0.5 ? up_hint.normalized() : Eigen::Vector3d::UnitZ();
  Eigen::Vector3d side = up.unitOrthogonal();
  const double distance = 0.66 * (hi - lo).norm();
  const Eigen::Vector3d eye = centre + distance * (std::sin(M_PI / 3) * up + std::cos(M_PI / 3) * side);
  const Eigen::Vector3d forward = (centre - eye).normalized();
  const Eigen::Vector3d right = forward.cross(up).normalized();
  Pose pose = Pose::Identity();
  pose.linear().col(0) = right;
  pose.linear().col(1) = forward.cross(right);  // image y down
  pose.linear().col(2) = forward;
  pose.translation() = eye;
  return pose;
}

int writePicture(const volume::LabeledVolume& map, const LabelLegend& legend, const ObjectsBenchOptions& o) {
  objects::ObjectParams params;
  params.up_from_floor = true;
  objects::ObjectTracker tracker(params, legend, map.voxelSize());
  const auto set = tracker.objectsOf(std::make_shared<const volume::LabeledVolume>(map.deepCopy()));
  Pose pose = overviewPose(map, set->up);
  if (!o.picture_pose.empty()) {
    auto read = readPoseMatrix(o.picture_pose);
    if (!read) {
      std::fprintf(stderr, "semfuse-bench objects: %s\n", read.error().c_str());
      return 2;
    }
    pose = read.value();
  }
  pose.translation() -= o.picture_back * pose.linear().col(2);
  const PinholeIntrinsics wide{960, 720, 520.0, 520.0, 479.5, 359.5};  // 85 degrees across
  auto written = writeObjectsPicture(map, *set, legend, pose, wide, o.picture);
  if (!written) {
    std::fprintf(stderr, "semfuse-bench objects: %s\n", written.error().c_str());
    return 1;
  }
  std::size_t objects = 0;
  for (const auto& object : set->objects) objects += object.fragment ? 0 : 1;
  std::printf("picture %s: %d of %zu objects in view, %.0f %% of the surface in view on an object\n", o.picture.c_str(),
              written.value().objects_in_view, objects, 100.0 * written.value().covered);
  return 0;
}

// A contiguous `share` of the map's leaves, starting at leaf `first` (wrapping), marked written.
void markLeavesChanged(volume::LabeledVolume& map, double share, std::size_t first) {
  std::vector<openvdb::Coord> origins;
  for (auto leaf = map.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf) origins.push_back(leaf->origin());
  if (origins.empty()) return;
  const auto count = static_cast<std::size_t>(share * static_cast<double>(origins.size()));
  std::vector<openvdb::Coord> changed;
  for (std::size_t i = 0; i < count; ++i) changed.push_back(origins[(first + i) % origins.size()]);
  map.markChanged(changed);
}

// The synthetic room fused with its ground-truth labels.
Result<volume::LabeledVolume> buildRoom(const ObjectsBenchOptions& o) {
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(o.scale);
  config.trajectory.frame_count = o.frames;
  synthetic::SyntheticSequence sequence(config);
  volume::VolumeParams params;
  params.voxel_size = o.voxel;
  params.truncation = 4 * o.voxel;
  params.integrate_color = false;
  auto created = volume::LabeledVolume::create(params);
  if (!created) return makeError(created.error());
  volume::LabeledVolume map = std::move(created).value();
  for (int i = 0; i < o.frames; ++i) {
    auto both = sequence.frameWithGroundTruth(i);
    if (!both) return makeError("frame " + std::to_string(i) + ": " + both.error());
    const auto& [frame, labels] = both.value();
    auto stats = volume::integrate(map, frame.depth, cv::Mat(), labels.labels, labels.confidence, frame.intrinsics,
                                   sequence.pose(i));
    if (!stats) return makeError("frame " + std::to_string(i) + ": " + stats.error());
  }
  return map;
}

int runObjectsBench(const ObjectsBenchOptions& o) {
  volume::LabeledVolume map;
  LabelLegend legend = *builtinLegend("synthetic");
  std::string what = "synthetic room (" + std::to_string(o.frames) + " frames)";
  if (!o.map.empty()) {
    auto loaded = volume::loadMap(o.map);
    if (!loaded) {
      std::fprintf(stderr, "semfuse-bench objects: %s\n", loaded.error().c_str());
      return 1;
    }
    map = std::move(loaded.value().volume);
    legend = loaded.value().legend;
    what = o.map;
  } else {
    auto built = buildRoom(o);
    if (!built) {
      std::fprintf(stderr, "semfuse-bench objects: %s\n", built.error().c_str());
      return 1;
    }
    map = std::move(built).value();
  }
  if (!o.picture.empty()) return writePicture(map, legend, o);
  // As the server's: up from the floor where the legend has one and the map enough of it.
  objects::ObjectParams params;
  params.up_from_floor = true;
  Timings first_query, changed_query, surface_only;
  Timings changed_surface, changed_grouping, changed_ids, changed_figures;
  std::size_t surface_voxels = 0, objects = 0, fragments = 0, scanned = 0, leaves = map.allocatedLeaves();
  objects::ObjectTracker incremental(params, legend, map.voxelSize());
  incremental.objectsOf(std::make_shared<const volume::LabeledVolume>(map.deepCopy()));  // untimed: fills the cache
  for (std::size_t r = 0; r < o.repeats; ++r) {
    auto snapshot = std::make_shared<const volume::LabeledVolume>(map.deepCopy());  // untimed
    Stopwatch surface_watch;
    surface_voxels = objects::extractSurface(*snapshot, legend).size();
    surface_only.add(surface_watch.elapsedMs());

    objects::ObjectTracker fresh(params, legend, map.voxelSize());
    Stopwatch watch;
    const auto set = fresh.objectsOf(snapshot);
    first_query.add(watch.elapsedMs());
    objects = fragments = 0;
    for (const auto& object : set->objects) (object.fragment ? fragments : objects) += 1;

    // The map's revisions go on from query to query, as a live map's do.
    markLeavesChanged(map, o.changed, r * leaves / o.repeats);
    auto changed_snapshot = std::make_shared<const volume::LabeledVolume>(map.deepCopy());  // untimed
    Stopwatch changed_watch;
    incremental.objectsOf(changed_snapshot);
    changed_query.add(changed_watch.elapsedMs());
    scanned = incremental.lastScannedLeaves();
    const objects::UpdateTimes times = incremental.lastUpdateTimes();
    changed_surface.add(times.surface);
    changed_grouping.add(times.grouping);
    changed_ids.add(times.ids);
    changed_figures.add(times.figures);
  }
  Table table("objects query, " + what + ", " + formatNumber(map.voxelSize() * 100, 0) + " cm voxels");
  table.add("surface voxels", std::to_string(surface_voxels));
  table.add("objects / fragments", std::to_string(objects) + " / " + std::to_string(fragments));
  table.addMs("surface extraction alone", surface_only);
  table.addMs("first query (surface, grouping, ids, figures)", first_query, "target <= 100 ms");
  table.add("first query / surface extraction", formatNumber(first_query.median() / surface_only.median(), 1) + "x");
  table.addMs("query after " + formatNumber(100 * o.changed, 0) + " % of the leaves changed", changed_query,
              "target <= 100 ms");
  table.add("leaves re-scanned / all", std::to_string(scanned) + " / " + std::to_string(leaves));
  table.addMs("  of which surface (cache + changed leaves)", changed_surface);
  table.addMs("  grouping", changed_grouping);
  table.addMs("  ids", changed_ids);
  table.addMs("  figures and frames", changed_figures);
  table.add("load average", formatNumber(loadAverage(), 2));
  table.print();
  return 0;
}

const bool objects_registered =
    registerBench("objects", "objects query time on the synthetic room", [](CLI::App& command) {
      auto options = std::make_shared<ObjectsBenchOptions>();
      command.add_option("--map", options->map, "a saved map file instead of the synthetic room (its legend is used)");
      command.add_option("--frames", options->frames, "synthetic frames to fuse")->capture_default_str();
      command.add_option("--scale", options->scale, "image scale of 640x480")->capture_default_str();
      command.add_option("--voxel", options->voxel, "voxel size, metres")->capture_default_str();
      command.add_option("--repeats", options->repeats, "timed queries of each kind")->capture_default_str();
      command.add_option("--changed", options->changed, "share of the leaves written between two queries")
          ->capture_default_str()
          ->check(CLI::Range(0.0, 1.0));
      command.add_option("--picture", options->picture,
                         "instead of timing, write a PNG of the objects, each id its colour, named by class and id");
      command.add_option(
          "--picture-pose", options->picture_pose,
          "the picture's camera: a file with a 4x4 camera-to-world matrix (a 7-Scenes frame-*.pose.txt); "
          "default: from above the map");
      command.add_option("--picture-back", options->picture_back, "move the picture's camera back this far, metres")
          ->capture_default_str();
      return [options] { return runObjectsBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
