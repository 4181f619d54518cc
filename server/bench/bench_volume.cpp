// semfuse-bench volume: integration speed and memory of the labeled volume on 7-Scenes frames
// (issue 3's benchmark). Frames are decoded outside the timed region; each timed figure is one
// integrate()/integrateLabels() call.
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <tbb/global_control.h>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::bench {
namespace {

struct VolumeBenchOptions {
  std::string data = redkitchenDir().string();
  std::size_t frames = 300;
  double voxel = 0.01;
  double truncation = 0.04;
  std::size_t baseline_frames = 100;
};

// A deterministic stand-in for a segmentation, at full depth resolution (the costliest case):
// bands of 30 cm of depth get labels 1..12, confidence rising across each band from 0.5 to 1.
struct SyntheticSegmentation {
  cv::Mat labels, confidence;
};
SyntheticSegmentation labelsFromDepthBands(const cv::Mat& depth) {
  SyntheticSegmentation seg{cv::Mat(depth.size(), CV_16UC1, cv::Scalar(0)),
                            cv::Mat(depth.size(), CV_32FC1, cv::Scalar(0))};
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const float d = depth.at<float>(v, u);
      if (!(d > 0)) continue;
      const float band = d / 0.3f;
      seg.labels.at<uint16_t>(v, u) = static_cast<uint16_t>(1 + static_cast<int>(band) % 12);
      seg.confidence.at<float>(v, u) = 0.5f + 0.5f * (band - std::floor(band));
    }
  return seg;
}

enum class Pass { kDepthColor, kDepthColorLabels, kSingleThreadLabels };

struct PassResult {
  Timings integrate, labels_only;
  Timings integrate_cpu, labels_only_cpu;  // CPU ms of all threads
  Timings leaves_touched;
  std::optional<volume::LabeledVolume> volume;
};

// Streams the frames through one volume; the late-label pass runs on the depth+colour volume
// right after each frame, as a late segmentation of that frame would.
Result<PassResult> runPass(const datasets::SevenScenesReader& reader, const volume::VolumeParams& params,
                           std::size_t frames, Pass pass) {
  PassResult result;
  result.volume.emplace(params);
  volume::LabeledVolume& map = *result.volume;
  for (std::size_t i = 0; i < frames; ++i) {
    auto frame = reader.load(i);
    if (!frame) return makeError("frame " + std::to_string(i) + ": " + frame.error());
    const Frame& f = frame.value();
    if (!f.camera_to_world) return makeError("frame " + std::to_string(i) + " has no pose");
    const SyntheticSegmentation seg = labelsFromDepthBands(f.depth);

    std::optional<tbb::global_control> single_thread;
    if (pass == Pass::kSingleThreadLabels) single_thread.emplace(tbb::global_control::max_allowed_parallelism, 1);
    const bool with_labels = pass != Pass::kDepthColor;
    Stopwatch watch;
    CpuStopwatch cpu;
    auto stats = volume::integrate(map, f.depth, f.color, with_labels ? seg.labels : cv::Mat(),
                                   with_labels ? seg.confidence : cv::Mat(), f.intrinsics, *f.camera_to_world);
    result.integrate.add(watch.elapsedMs());
    result.integrate_cpu.add(cpu.elapsedMs());
    if (!stats) return makeError("integrate frame " + std::to_string(i) + ": " + stats.error());
    result.leaves_touched.add(static_cast<double>(stats.value().leaves_touched));

    if (pass == Pass::kDepthColor) {
      Stopwatch late;
      CpuStopwatch late_cpu;
      auto label_stats = volume::integrateLabels(map, f.depth, seg.labels, seg.confidence, f.intrinsics,
                                                 *f.camera_to_world);
      result.labels_only.add(late.elapsedMs());
      result.labels_only_cpu.add(late_cpu.elapsedMs());
      if (!label_stats) return makeError("integrateLabels frame " + std::to_string(i) + ": " + label_stats.error());
    }
  }
  return result;
}

int runVolumeBench(const VolumeBenchOptions& options) {
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", reader.error().c_str());
    return 2;
  }
  const std::size_t frames = std::min(options.frames, reader.value().count());
  volume::VolumeParams params;
  params.voxel_size = options.voxel;
  params.truncation = options.truncation;
  if (Status valid = params.validate(); !valid) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", valid.error().c_str());
    return 2;
  }
  const PinholeIntrinsics& k = reader.value().intrinsics();
  std::printf("semfuse-bench volume: %zu frames of %s (%dx%d), voxel %.3f m, truncation %.3f m, %d threads, "
              "load average %.2f at start\n",
              frames, options.data.c_str(), k.width, k.height, params.voxel_size, params.truncation,
              static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)),
              loadAverage());

  // The labeled pass first, alone, so that peak RSS is one map (plus one frame in flight).
  auto labeled = runPass(reader.value(), params, frames, Pass::kDepthColorLabels);
  if (!labeled) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", labeled.error().c_str());
    return 1;
  }
  const double peak_rss = peakRssMiB();
  const volume::LabeledVolume& map = *labeled.value().volume;
  const double voxels = static_cast<double>(map.allocatedVoxels());
  const double geometry_bytes = static_cast<double>(map.geometryMemoryBytes());
  const double all_bytes = static_cast<double>(map.memoryBytes());
  const std::string leaves_and_voxels =
      std::to_string(map.allocatedLeaves()) + " / " + std::to_string(map.allocatedVoxels());
  const std::string observed = std::to_string(map.observedVoxels()) + " observed (weight > 0)";
  labeled.value().volume.reset();  // free the map before the other passes build theirs

  auto unlabeled = runPass(reader.value(), params, frames, Pass::kDepthColor);
  const std::size_t baseline_frames = std::min(options.baseline_frames, frames);
  auto single = runPass(reader.value(), params, baseline_frames, Pass::kSingleThreadLabels);
  if (!unlabeled || !single) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", (!unlabeled ? unlabeled.error() : single.error()).c_str());
    return 1;
  }

  const Timings& with_labels = labeled.value().integrate;
  // The same frames, for a like-for-like speed-up figure.
  Timings parallel_prefix;
  {
    auto prefix = runPass(reader.value(), params, baseline_frames, Pass::kDepthColorLabels);
    if (prefix) parallel_prefix = prefix.value().integrate;
  }
  Table table("labeled volume (median / p95 per frame; targets from issue 3)");
  auto cpu = [](const Timings& t) { return "CPU " + formatNumber(t.median()) + " ms (all threads)"; };
  table.addMs("integrate depth+colour", unlabeled.value().integrate, cpu(unlabeled.value().integrate_cpu));
  table.addMs("integrate depth+colour+labels", with_labels,
              cpu(labeled.value().integrate_cpu) + "; target <= 7 ms; Open3D ScalableTSDFVolume 18.7 ms (x" +
                  formatNumber(18.7 / with_labels.median(), 1) + ")");
  table.addMs("labels only (late segmentation)", unlabeled.value().labels_only, cpu(unlabeled.value().labels_only_cpu));
  table.addMs("integrate+labels, 1 thread, first " + std::to_string(baseline_frames), single.value().integrate,
              "parallel on the same frames: " + formatNumber(parallel_prefix.median()) + " ms, speed-up x" +
                  formatNumber(single.value().integrate.median() / parallel_prefix.median(), 2));
  table.add("raycast 640x480 depth+normal+label", "-", "target <= 33 ms: semfuse-bench render");
  table.add("mesh (marching cubes, labels)", "-", "target <= 100 ms: semfuse-bench render");
  table.add("leaves touched per frame", formatNumber(labeled.value().leaves_touched.median(), 0), "median");
  table.add("allocated leaves / voxels", leaves_and_voxels, observed);
  table.add("bytes per allocated voxel, geometry+labels", formatNumber(geometry_bytes / voxels, 3),
            "target <= 8 + tree overhead");
  table.add("bytes per allocated voxel, with colour", formatNumber(all_bytes / voxels, 3));
  table.add("map memory", formatNumber(all_bytes / (1024.0 * 1024.0), 1) + " MiB");
  table.add("peak RSS", formatNumber(peak_rss, 1) + " MiB", "after the labeled pass: one map + one frame");
  table.print();
  std::printf("load average at the end: %.2f (timings are wall clock; other work on the machine inflates them)\n",
              loadAverage());
  return 0;
}

const bool registered = registerBench(
    "volume", "integration speed and memory of the labeled volume (7-Scenes frames)", [](CLI::App& command) {
      auto options = std::make_shared<VolumeBenchOptions>();
      command.add_option("--data", options->data, "7-Scenes sequence folder")->capture_default_str();
      command.add_option("--frames", options->frames, "frames to integrate (from frame 0)")->capture_default_str();
      command.add_option("--voxel", options->voxel, "voxel size, metres")->capture_default_str();
      command.add_option("--trunc", options->truncation, "truncation, metres")->capture_default_str();
      command.add_option("--baseline-frames", options->baseline_frames,
                         "frames for the single-thread baseline")->capture_default_str();
      return [options] { return runVolumeBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
