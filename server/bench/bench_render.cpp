// semfuse-bench render: raycast and mesh speed on the 7-Scenes map (targets: raycast 640x480
// depth+normal+label <= 33 ms, mesh <= 100 ms). The map is built once, untimed, from the
// frames with their reference poses; the raycast baseline in the same run marches voxel by voxel
// through unallocated space instead of skipping it with the tree.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <tbb/global_control.h>
#include <opencv2/core.hpp>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/core/malloc_tuning.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/ply_writer.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::bench {
namespace {

struct RenderBenchOptions {
  std::string data = redkitchenDir().string();
  std::size_t frames = 300;
  double voxel = 0.01;
  double truncation = 0.04;
  std::size_t views = 6;    // raycast poses, spread over the integrated frames
  std::size_t repeats = 3;  // timed runs per pose and per mesh
  bool baseline = true;     // also time the raycast without empty-space skipping (slow)
};

Result<volume::LabeledVolume> buildMap(const datasets::SevenScenesReader& reader, const volume::VolumeParams& params,
                                       std::size_t frames) {
  volume::LabeledVolume map(params);
  for (std::size_t i = 0; i < frames; ++i) {
    auto frame = reader.loadDepthOnly(i);
    if (!frame) return makeError("frame " + std::to_string(i) + ": " + frame.error());
    auto stats = volume::integrate(map, frame.value());
    if (!stats) return makeError("integrate frame " + std::to_string(i) + ": " + stats.error());
  }
  return map;
}

// Wall-clock and CPU (all threads) milliseconds of repeated runs: on a loaded machine the wall
// figures grow with the load, CPU time much less.
struct TimedRuns {
  Timings wall, cpu;
};

// A raycast configuration to time: which layers and skipping, and which voxel reader.
struct RaycastVariant {
  render::RaycastOptions options;
  render::RaycastKernel kernel;
};

// Times every variant on every pose, `repeats` times, the variants alternating run by run so that
// they see the same load; `hit_fractions` gets each variant's share of pixels with a surface.
std::vector<TimedRuns> timeRaycasts(const volume::LabeledVolume& map, const PinholeIntrinsics& k,
                                    const std::vector<Pose>& poses, const std::vector<RaycastVariant>& variants,
                                    std::size_t repeats, std::vector<double>& hit_fractions) {
  std::vector<TimedRuns> timings(variants.size());
  hit_fractions.assign(variants.size(), 0.0);
  const render::RaycastKernel default_kernel = render::raycastKernel();
  for (const Pose& pose : poses)
    for (std::size_t r = 0; r < repeats; ++r)
      for (std::size_t v = 0; v < variants.size(); ++v) {
        render::setRaycastKernel(variants[v].kernel);
        Stopwatch watch;
        CpuStopwatch cpu;
        auto images = render::raycast(map, k, pose, variants[v].options);
        timings[v].wall.add(watch.elapsedMs());
        timings[v].cpu.add(cpu.elapsedMs());
        if (!images) std::fprintf(stderr, "semfuse-bench render: raycast: %s\n", images.error().c_str());
        if (images && r == 0)
          hit_fractions[v] += cv::countNonZero(images.value().depth) / static_cast<double>(k.width * k.height);
      }
  render::setRaycastKernel(default_kernel);
  for (double& fraction : hit_fractions) fraction = poses.empty() ? 0.0 : fraction / poses.size();
  return timings;
}

int runRenderBench(const RenderBenchOptions& options) {
  keepScratchResident();  // as semfuse-server does, whose work this times
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) {
    std::fprintf(stderr, "semfuse-bench render: %s\n", reader.error().c_str());
    return 2;
  }
  const std::size_t frames = std::min(options.frames, reader.value().count());
  volume::VolumeParams params;
  params.voxel_size = options.voxel;
  params.truncation = options.truncation;
  params.integrate_color = false;                    // the timed layers do not read colour
  params.label_rule = volume::LabelRule::kEvidence;  // depth only: no label sidecar to allocate and copy
  if (Status valid = params.validate(); !valid || frames == 0) {
    std::fprintf(stderr, "semfuse-bench render: %s\n", valid ? "no frames" : valid.error().c_str());
    return 2;
  }
  auto first = reader.value().loadDepthOnly(0);
  if (!first) {
    std::fprintf(stderr, "semfuse-bench render: %s\n", first.error().c_str());
    return 2;
  }
  const PinholeIntrinsics k = first.value().intrinsics;  // with the image size filled in
  std::printf(
      "semfuse-bench render: map of %zu frames of %s, voxel %.3f m, truncation %.3f m, %d threads, %s voxel reader\n",
      frames, options.data.c_str(), params.voxel_size, params.truncation,
      static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)),
      render::raycastKernelName(render::raycastKernel()));
  Stopwatch build_watch;
  auto map = buildMap(reader.value(), params, frames);
  if (!map) {
    std::fprintf(stderr, "semfuse-bench render: %s\n", map.error().c_str());
    return 1;
  }
  const double build_s = build_watch.elapsedMs() / 1000.0;

  std::vector<Pose> poses;
  for (std::size_t v = 0; v < options.views; ++v) {
    auto frame = reader.value().loadDepthOnly(v * frames / std::max<std::size_t>(options.views, 1));
    if (frame && frame.value().camera_to_world) poses.push_back(*frame.value().camera_to_world);
  }
  render::RaycastOptions fast{kDepthLayer | kNormalsLayer | kLabelsLayer};
  render::RaycastOptions baseline = fast;
  baseline.skip_empty_space = false;
  render::RaycastOptions depth_only{kDepthLayer};
  const render::RaycastKernel kernel = render::raycastKernel();
  // The portable kernels (voxel reader, bounds) beside the default where the default is AVX2.
  const bool compare_kernels = kernel == render::RaycastKernel::kAvx2;
  std::vector<RaycastVariant> variants{{fast, kernel}, {depth_only, kernel}};
  if (compare_kernels) variants.push_back({fast, render::RaycastKernel::kScalar});
  std::vector<double> hits;
  const std::vector<TimedRuns> raycasts = timeRaycasts(map.value(), k, poses, variants, options.repeats, hits);
  const TimedRuns& raycast_fast = raycasts[0];
  const TimedRuns& raycast_depth = raycasts[1];
  const double fast_hits = hits[0];
  // What the server does under its map lock before each raycast query: copy the leaves in view.
  TimedRuns prepare;
  for (const Pose& pose : poses)
    for (std::size_t r = 0; r < options.repeats; ++r) {
      Stopwatch watch;
      CpuStopwatch cpu;
      auto prepared = render::prepareRaycast(map.value(), k, pose, fast);
      prepare.wall.add(watch.elapsedMs());
      prepare.cpu.add(cpu.elapsedMs());
      if (!prepared) std::fprintf(stderr, "semfuse-bench render: prepare: %s\n", prepared.error().c_str());
    }
  std::vector<double> baseline_hits;
  const TimedRuns raycast_baseline =
      options.baseline ? timeRaycasts(map.value(), k, poses, {{baseline, kernel}}, options.repeats, baseline_hits)[0]
                       : TimedRuns{};

  TimedRuns mesh_timings, mesh_vtm_timings;
  Timings ply_timings;
  std::size_t vertices = 0, triangles = 0, vtm_vertices = 0, vtm_triangles = 0, ply_size = 0;
  const LabelLegend legend;
  // The default mesher (surface nets) is the timed figure; OpenVDB's VolumeToMesh, the former
  // default, alternates with it in the same loop, so both see the same load.
  render::MeshOptions volume_to_mesh;
  volume_to_mesh.method = render::MeshMethod::kOpenVdbVolumeToMesh;
  for (std::size_t r = 0; r < options.repeats; ++r) {
    Stopwatch vtm_watch;
    CpuStopwatch vtm_cpu;
    auto vtm = render::extractMesh(map.value(), volume_to_mesh);
    mesh_vtm_timings.wall.add(vtm_watch.elapsedMs());
    mesh_vtm_timings.cpu.add(vtm_cpu.elapsedMs());
    if (vtm) {
      vtm_vertices = vtm.value().vertices.size();
      vtm_triangles = vtm.value().triangles.size();
    }
    Stopwatch watch;
    CpuStopwatch cpu;
    auto mesh = render::extractMesh(map.value());
    mesh_timings.wall.add(watch.elapsedMs());
    mesh_timings.cpu.add(cpu.elapsedMs());
    if (!mesh) {
      std::fprintf(stderr, "semfuse-bench render: %s\n", mesh.error().c_str());
      return 1;
    }
    vertices = mesh.value().vertices.size();
    triangles = mesh.value().triangles.size();
    Stopwatch ply_watch;
    auto bytes = render::plyBytes(mesh.value(), legend);
    ply_timings.add(ply_watch.elapsedMs());
    ply_size = bytes ? bytes.value().size() : 0;
  }

  Table table("render (median / p95 over " + std::to_string(poses.size()) + " poses x " +
              std::to_string(options.repeats) + " runs; targets beside them)");
  auto cpu = [](const TimedRuns& t) { return "CPU " + formatNumber(t.cpu.median()) + " ms (all threads); "; };
  table.addMs("raycast 640x480 depth+normal+label", raycast_fast.wall,
              cpu(raycast_fast) + "target <= 33 ms; Open3D VoxelBlockGrid 83 ms (x" +
                  formatNumber(83.0 / raycast_fast.wall.median(), 2) + "); " + formatNumber(100 * fast_hits, 1) +
                  "% pixels hit");
  if (options.baseline)
    table.addMs("  baseline: no empty-space skipping", raycast_baseline.wall,
                cpu(raycast_baseline) + "skipping is x" +
                    formatNumber(raycast_baseline.cpu.median() / raycast_fast.cpu.median(), 2) + " less CPU");
  table.addMs("raycast 640x480 depth only", raycast_depth.wall, cpu(raycast_depth));
  table.addMs("  prepareRaycast (server, under lock)", prepare.wall,
              cpu(prepare) + "copy of the leaves in view, part of the above");
  if (compare_kernels)
    table.addMs("  d+n+l, portable kernels", raycasts[2].wall,
                cpu(raycasts[2]) + "the " + render::raycastKernelName(kernel) + " kernels take x" +
                    formatNumber(raycast_fast.cpu.median() / raycasts[2].cpu.median(), 2) + " its CPU");
  table.addMs("mesh (surface nets + labels)", mesh_timings.wall,
              cpu(mesh_timings) + "target <= 100 ms; vdbfusion 262 ms (x" +
                  formatNumber(262.0 / mesh_timings.wall.median(), 2) + ")");
  table.addMs("  VolumeToMesh (option)", mesh_vtm_timings.wall,
              cpu(mesh_vtm_timings) + "surface nets take x" +
                  formatNumber(mesh_timings.cpu.median() / mesh_vtm_timings.cpu.median(), 2) + " its CPU");
  table.add("mesh size", std::to_string(vertices) + " vertices", std::to_string(triangles) + " triangles");
  table.add("  VolumeToMesh", std::to_string(vtm_vertices) + " vertices", std::to_string(vtm_triangles) + " triangles");
  table.addMs("PLY to memory", ply_timings, formatNumber(ply_size / (1024.0 * 1024.0), 1) + " MiB");
  table.add("map", std::to_string(map.value().allocatedLeaves()) + " leaves",
            "built in " + formatNumber(build_s, 1) + " s (untimed above)");
  table.add("load average (1 min) at the end", formatNumber(loadAverage()),
            "2 cores; above 2 the wall times are inflated");
  table.print();
  return 0;
}

const bool render_registered =
    registerBench("render", "raycast and mesh speed on the 7-Scenes map", [](CLI::App& command) {
      auto options = std::make_shared<RenderBenchOptions>();
      addMapOptions(command, options->data, options->voxel, options->truncation);
      command.add_option("--frames", options->frames, "frames to integrate (from frame 0)")->capture_default_str();
      command.add_option("--views", options->views, "raycast poses")->capture_default_str();
      command.add_option("--repeats", options->repeats, "timed runs per pose / mesh")->capture_default_str();
      command
          .add_flag("--baseline,!--no-baseline", options->baseline,
                    "also time the raycast without empty-space skipping")
          ->capture_default_str();
      return [options] { return runRenderBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
