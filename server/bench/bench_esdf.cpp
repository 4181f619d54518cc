// semfuse-bench esdf: the distance field on 7-Scenes frames (server/esdf/README.md). Per frame:
// integration (depth + labels), observed free space, and the field's update from the changed
// leaves (copy under the map's lock + waves); at the end a full recompute, 10,000 point queries,
// occupancy slices, semantic distance and memory. Frames are decoded outside the timed region.
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/core/malloc_tuning.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/esdf/distance_queries.hpp"
#include "semfuse/esdf/esdf_map.hpp"
#include "semfuse/esdf/semantic_distance.hpp"
#include "semfuse/volume/free_space.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::bench {
namespace {

struct EsdfBenchOptions {
  std::string data = redkitchenDir().string();
  std::size_t frames = 500;
  double voxel = 0.05;
  double truncation = 0.0;  // 0: 4 voxels
  double max_distance = 2.0;
  double field_voxel = 0.0;  // 0: EsdfParams chooses
  int queries = 10000;
  int repeats = 50;
};

// Labels for the semantic queries: bands of 30 cm of depth get labels 1..12 (as bench volume).
cv::Mat labelsFromDepth(const cv::Mat& depth) {
  cv::Mat labels(depth.size(), CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const float d = depth.at<float>(v, u);
      if (d > 0) labels.at<uint16_t>(v, u) = static_cast<uint16_t>(1 + static_cast<int>(d / 0.3f) % 12);
    }
  return labels;
}

// How far the field kept up frame by frame lies from one computed from scratch on the same map:
// the price of updating only what changed.
struct FieldAgreement {
  std::size_t compared = 0, over_half = 0, over_one = 0;
  double p99 = 0.0, worst = 0.0;
};

FieldAgreement compareWithRebuild(const esdf::EsdfMap& field, const esdf::EsdfMap& rebuilt) {
  FieldAgreement result;
  Timings differences;
  openvdb::tree::ValueAccessor<const esdf::EsdfGrid::TreeType> values(rebuilt.grid().tree());
  const float max_voxels = field.maxDistanceVoxels();
  for (auto it = field.grid().tree().cbeginValueOn(); it; ++it) {
    esdf::PackedEsdf packed;
    if (!values.probeValue(it.getCoord(), packed)) continue;
    const double difference = std::abs(esdf::unpackEsdf(*it).signedDistance(max_voxels) -
                                       esdf::unpackEsdf(packed).signedDistance(max_voxels));
    ++result.compared;
    result.over_half += difference > 0.5;
    result.over_one += difference > 1.0;
    result.worst = std::max(result.worst, difference);
    differences.add(difference);
  }
  result.p99 = differences.percentile(99);
  return result;
}

int runEsdfBench(const EsdfBenchOptions& options) {
  keepScratchResident();
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) {
    std::fprintf(stderr, "semfuse-bench esdf: %s\n", reader.error().c_str());
    return 2;
  }
  volume::VolumeParams params;
  params.voxel_size = options.voxel;
  params.truncation = options.truncation > 0 ? options.truncation : 4 * options.voxel;
  params.label_rule = volume::LabelRule::kEvidence;
  params.label_classes = 13;
  params.integrate_color = false;
  esdf::EsdfParams esdf_params;
  esdf_params.max_distance = options.max_distance;
  esdf_params.voxel_size = options.field_voxel;
  if (Status ok = params.validate(); !ok)
    return std::fprintf(stderr, "semfuse-bench esdf: %s\n", ok.error().c_str()), 2;
  if (Status ok = esdf_params.validate(params.voxel_size, params.truncation); !ok)
    return std::fprintf(stderr, "semfuse-bench esdf: %s\n", ok.error().c_str()), 2;
  const std::size_t frames = std::min(options.frames, reader.value().count());
  const double field_voxel = esdf_params.fieldVoxel(params.voxel_size, params.truncation);
  const int stride = esdf_params.stride(params.voxel_size, params.truncation);
  std::printf(
      "semfuse-bench esdf: %zu frames of %s, voxel %.3f m, truncation %.3f m, field voxel %.3f m, max distance "
      "%.2f m, load average %.2f at start\n",
      frames, options.data.c_str(), params.voxel_size, params.truncation, field_voxel, esdf_params.max_distance,
      loadAverage());

  volume::LabeledVolume map(params);
  esdf::EsdfMap field(field_voxel, esdf_params);
  Timings integrate, free_space, copy, apply, update, update_cpu, leaves, added, removed, cleared, relaxed, popped;
  for (std::size_t i = 0; i < frames; ++i) {
    auto frame = reader.value().loadDepthOnly(i);
    if (!frame || !frame.value().camera_to_world) {
      std::fprintf(stderr, "semfuse-bench esdf: frame %zu unreadable or without pose\n", i);
      return 1;
    }
    const Frame& f = frame.value();
    const cv::Mat labels = labelsFromDepth(f.depth);
    Stopwatch integrate_watch;
    if (!volume::integrate(map, f.depth, cv::Mat(), labels, cv::Mat(), f.intrinsics, *f.camera_to_world)) return 1;
    integrate.add(integrate_watch.elapsedMs());
    Stopwatch free_watch;
    if (!volume::observeFreeSpace(map, f.depth, f.intrinsics, *f.camera_to_world, stride)) return 1;
    free_space.add(free_watch.elapsedMs());

    Stopwatch update_watch;
    CpuStopwatch update_cpu_watch;
    const esdf::MapChanges changes = esdf::copyChanges(map, field.revision(), stride);
    copy.add(update_watch.elapsedMs());
    Stopwatch apply_watch;
    const esdf::UpdateStats stats = field.apply(changes);
    apply.add(apply_watch.elapsedMs());
    added.add(static_cast<double>(stats.sites_added));
    removed.add(static_cast<double>(stats.sites_removed));
    cleared.add(static_cast<double>(stats.cleared));
    relaxed.add(static_cast<double>(stats.relaxed));
    popped.add(static_cast<double>(stats.popped));
    update.add(update_watch.elapsedMs());
    update_cpu.add(update_cpu_watch.elapsedMs());
    leaves.add(static_cast<double>(changes.leaves.size()));
  }

  // Full recompute of the same map.
  Timings rebuild;
  std::unique_ptr<esdf::EsdfMap> rebuilt;
  for (int r = 0; r < 3; ++r) {
    rebuilt = std::make_unique<esdf::EsdfMap>(field_voxel, esdf_params);
    Stopwatch watch;
    rebuilt->apply(esdf::copyChanges(map, 0, stride));
    rebuild.add(watch.elapsedMs());
  }
  const FieldAgreement agreement = compareWithRebuild(field, *rebuilt);

  // Points spread over the field's observed extent (a planner's are near the robot: no easier).
  const openvdb::CoordBBox box = field.grid().evalActiveVoxelBoundingBox();
  const Eigen::Vector3d lo = Eigen::Vector3d(box.min().x(), box.min().y(), box.min().z()) * field_voxel;
  const Eigen::Vector3d hi = Eigen::Vector3d(box.max().x(), box.max().y(), box.max().z()) * field_voxel;
  std::mt19937 random(3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < options.queries; ++i) {
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = std::uniform_real_distribution<double>(lo[a], hi[a])(random);
    points.push_back(p);
  }
  // Wall and CPU: on a loaded machine a batch of a millisecond is often descheduled midway, which
  // shows in the wall p95 and not in the CPU time.
  Timings queries, queries_cpu;
  std::size_t known = 0;
  for (int r = 0; r < options.repeats; ++r) {
    Stopwatch watch;
    CpuStopwatch cpu_watch;
    const auto samples = esdf::distancesAt(field, points);
    queries.add(watch.elapsedMs());
    queries_cpu.add(cpu_watch.elapsedMs());
    known = 0;
    for (const auto& s : samples) known += s.known;
  }

  // A 0.5 m band through the middle of the map's z extent (7-Scenes' world frame is the first
  // camera's, not gravity-aligned: this times the slice, it is no floor plan).
  esdf::OccupancyRequest slice_request;
  slice_request.z_min = 0.5 * (lo.z() + hi.z()) - 0.25;
  slice_request.z_max = slice_request.z_min + 0.5;
  slice_request.inflation_radius = 0.2;
  Timings slices;
  esdf::OccupancyGrid slice;
  for (int r = 0; r < options.repeats; ++r) {
    Stopwatch watch;
    slice = esdf::occupancySlice(field, slice_request);
    slices.add(watch.elapsedMs());
  }

  Timings semantic_build, semantic_queries;
  std::size_t surface_points = 0;
  for (int r = 0; r < 10; ++r) {
    Stopwatch build;
    const esdf::SurfaceIndex index(field.surfaces().gather({3, 4}));
    semantic_build.add(build.elapsedMs());
    surface_points = index.size();
    Stopwatch watch;
    const auto samples = esdf::semanticDistances(index, points);
    semantic_queries.add(watch.elapsedMs());
  }

  const double esdf_voxels = static_cast<double>(field.grid().tree().leafCount()) * volume::LabeledVolume::kLeafVoxels;
  Table table("distance field (median / p95; targets beside them)");
  table.addMs("integrate depth+labels", integrate, "for scale");
  table.addMs("observe free space", free_space, "per frame, before the field's update");
  table.addMs("field update after a frame", update,
              "copy " + formatNumber(copy.median()) + " + waves " + formatNumber(apply.median()) + " ms; CPU " +
                  formatNumber(update_cpu.median()) + " ms; target <= 10 ms");
  table.add("leaves per update", formatNumber(leaves.median(), 0) + " / " + formatNumber(leaves.p95(), 0),
            "changed leaves and their face neighbours");
  table.add("sites added / removed per update",
            formatNumber(added.median(), 0) + " / " + formatNumber(removed.median(), 0),
            "median; voxels cleared " + formatNumber(cleared.median(), 0) + ", relaxed " +
                formatNumber(relaxed.median(), 0) + ", taken from the queue " + formatNumber(popped.median(), 0));
  table.addMs("full recompute", rebuild,
              std::to_string(rebuilt->knownVoxels()) + " known voxels; x" +
                  formatNumber(rebuild.median() / update.median(), 0) + " an update");
  table.add("incremental field against the recompute",
            formatNumber(agreement.p99, 2) + " / " + formatNumber(agreement.worst, 2) + " voxel",
            "p99 / max difference over " + std::to_string(agreement.compared) + " voxels; " +
                std::to_string(agreement.over_half) + " differ by more than 0.5 voxel, " +
                std::to_string(agreement.over_one) + " by more than 1");
  table.addMs(std::to_string(options.queries) + " point queries (distance + gradient)", queries,
              formatNumber(100.0 * known / points.size(), 0) + "% known; CPU " + formatNumber(queries_cpu.median()) +
                  " / " + formatNumber(queries_cpu.p95()) + " ms; target <= 2 ms");
  table.addMs("occupancy slice, 0.5 m band, inflation 0.2 m", slices,
              std::to_string(slice.width) + " x " + std::to_string(slice.height) + " cells; target <= 20 ms");
  table.addMs("semantic index of 2 labels (gather + KD-tree)", semantic_build,
              std::to_string(surface_points) + " surface points");
  table.addMs(std::to_string(options.queries) + " semantic distance queries", semantic_queries);
  table.add("known voxels", std::to_string(field.knownVoxels()),
            std::to_string(field.grid().tree().leafCount()) + " leaves");
  table.add("bytes per field voxel", formatNumber(static_cast<double>(field.grid().memUsage()) / esdf_voxels, 2),
            "allocated voxels (8 + tree); per known voxel " +
                formatNumber(static_cast<double>(field.grid().memUsage()) / field.knownVoxels(), 2));
  table.add("field memory", formatNumber(field.memoryBytes() / (1024.0 * 1024.0), 1) + " MiB",
            "surface points " + formatNumber(field.surfaces().memoryBytes() / (1024.0 * 1024.0), 1) + " MiB; TSDF " +
                formatNumber(map.memoryBytes() / (1024.0 * 1024.0), 1) + " MiB");
  table.add("free space mask",
            formatNumber(map.freeSpaceGrid() ? map.freeSpaceGrid()->memUsage() / (1024.0 * 1024.0) : 0.0, 2) + " MiB");
  table.print();
  std::printf("load average at the end: %.2f\n", loadAverage());
  return 0;
}

const bool esdf_registered = registerBench(
    "esdf", "distance field update, recompute, queries, slices and memory (7-Scenes frames)", [](CLI::App& command) {
      auto options = std::make_shared<EsdfBenchOptions>();
      addMapOptions(command, options->data, options->voxel, options->truncation, "0: 4 voxels");
      command.add_option("--frames", options->frames, "frames to integrate (from frame 0)")->capture_default_str();
      command.add_option("--max-distance", options->max_distance, "the field's maximum distance, metres")
          ->capture_default_str();
      command
          .add_option("--field-voxel", options->field_voxel,
                      "the field's voxel size, metres: a whole multiple of --voxel, at most the truncation (0: "
                      "--voxel)")
          ->capture_default_str();
      command.add_option("--queries", options->queries, "points per query batch")->capture_default_str();
      command.add_option("--repeats", options->repeats, "repetitions of each query")->capture_default_str();
      return [options] { return runEsdfBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
