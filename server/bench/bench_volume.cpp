// semfuse-bench volume: integration speed and memory of the labeled volume on 7-Scenes frames
// (server/volume/README.md). Frames are decoded outside the timed region; each timed figure is one
// integrate()/integrateLabels() call.
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <tbb/global_control.h>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/core/malloc_tuning.hpp"
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
  std::string kernel;                   // "scalar" or "avx2"; empty: the default (widest available)
  bool compare_kernels = false;         // only the interleaved scalar-vs-avx2 comparison
  bool compare_rules = false;           // only the interleaved evidence-vs-bayes comparison
  std::string label_rule = "evidence";  // the paper's rule; the server's default is bayes
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
      auto label_stats =
          volume::integrateLabels(map, f.depth, seg.labels, seg.confidence, f.intrinsics, *f.camera_to_world);
      result.labels_only.add(late.elapsedMs());
      result.labels_only_cpu.add(late_cpu.elapsedMs());
      if (!label_stats) return makeError("integrateLabels frame " + std::to_string(i) + ": " + label_stats.error());
    }
  }
  return result;
}

// Bits of every leaf of `a` equal those in `b` (values and active masks), and the leaf sets match;
// returns the number of differing voxels (+ missing leaves' voxels).
template <typename Grid>
std::size_t differingVoxels(const Grid* a, const Grid* b) {
  if (!a || !b) return a == b ? 0 : 1;
  std::size_t differing = 0;
  for (auto leaf = a->tree().cbeginLeaf(); leaf; ++leaf) {
    const auto* other = b->tree().probeConstLeaf(leaf->origin());
    if (!other) {
      differing += leaf->SIZE;
      continue;
    }
    for (openvdb::Index i = 0; i < leaf->SIZE; ++i)
      differing += leaf->getValue(i) != other->getValue(i) || leaf->isValueOn(i) != other->isValueOn(i);
  }
  return differing + (a->tree().leafCount() != b->tree().leafCount() ? 1 : 0);
}

// Two set-ups (a kernel, map parameters) on the same frames, interleaved frame by frame
// (alternating which goes first) so that the machine's load hits both alike: labeled frames into
// one volume each, and geometry then a late-label pass into one more each.
struct Setup {
  std::string name;
  volume::IntegrationKernel kernel;
  volume::VolumeParams params;
};
struct Interleaved {
  std::optional<volume::LabeledVolume> labeled, late;
  Timings integrate, integrate_cpu, labels_only, labels_only_cpu;
};
Result<std::array<Interleaved, 2>> interleave(const datasets::SevenScenesReader& reader,
                                              const std::array<Setup, 2>& setups, std::size_t frames) {
  std::array<Interleaved, 2> runs;
  for (int k = 0; k < 2; ++k) runs[k].labeled.emplace(setups[k].params), runs[k].late.emplace(setups[k].params);
  for (std::size_t i = 0; i < frames; ++i) {
    auto frame = reader.load(i);
    if (!frame || !frame.value().camera_to_world)
      return makeError("frame " + std::to_string(i) + " unreadable or without pose");
    const Frame& f = frame.value();
    const SyntheticSegmentation seg = labelsFromDepthBands(f.depth);
    for (int n = 0; n < 2; ++n) {
      const int k = (static_cast<int>(i) + n) % 2;
      volume::setIntegrationKernel(setups[k].kernel);
      Interleaved& r = runs[k];
      Stopwatch watch;
      CpuStopwatch cpu;
      auto stats =
          volume::integrate(*r.labeled, f.depth, f.color, seg.labels, seg.confidence, f.intrinsics, *f.camera_to_world);
      r.integrate.add(watch.elapsedMs());
      r.integrate_cpu.add(cpu.elapsedMs());
      auto geometry = volume::integrate(*r.late, f.depth, f.color, f.intrinsics, *f.camera_to_world);
      Stopwatch late;
      CpuStopwatch late_cpu;
      auto labels =
          volume::integrateLabels(*r.late, f.depth, seg.labels, seg.confidence, f.intrinsics, *f.camera_to_world);
      r.labels_only.add(late.elapsedMs());
      r.labels_only_cpu.add(late_cpu.elapsedMs());
      if (!stats || !geometry || !labels) return makeError("frame " + std::to_string(i) + " failed");
    }
  }
  return runs;
}

// The interleaved runs' times, and the second's over the first's.
Table interleavedTable(const std::string& title, const std::array<Setup, 2>& setups,
                       const std::array<Interleaved, 2>& runs) {
  Table table(title);
  auto ratio = [](const Timings& first, const Timings& second) {
    return formatNumber(second.median() / first.median(), 2);
  };
  for (int k = 0; k < 2; ++k) {
    table.addMs("integrate depth+colour+labels, " + setups[k].name, runs[k].integrate,
                "CPU " + formatNumber(runs[k].integrate_cpu.median()) + " ms (all threads)");
    table.addMs("labels only (late segmentation), " + setups[k].name, runs[k].labels_only,
                "CPU " + formatNumber(runs[k].labels_only_cpu.median()) + " ms (all threads)");
  }
  const std::string over = setups[1].name + " / " + setups[0].name;
  table.add(over + ", integrate+labels", "x" + ratio(runs[0].integrate, runs[1].integrate),
            "CPU x" + ratio(runs[0].integrate_cpu, runs[1].integrate_cpu));
  table.add(over + ", labels only", "x" + ratio(runs[0].labels_only, runs[1].labels_only),
            "CPU x" + ratio(runs[0].labels_only_cpu, runs[1].labels_only_cpu));
  return table;
}

// The scalar and AVX2 kernels, interleaved; then the two maps compared voxel for voxel.
int compareKernels(const datasets::SevenScenesReader& reader, const volume::VolumeParams& params, std::size_t frames) {
  using volume::IntegrationKernel;
  if (!volume::integrationKernelAvailable(IntegrationKernel::kAvx2)) {
    std::fprintf(stderr, "semfuse-bench volume: the AVX2 kernel is not available on this CPU/build\n");
    return 2;
  }
  const std::array<Setup, 2> setups{Setup{"scalar", IntegrationKernel::kScalar, params},
                                    Setup{"avx2", IntegrationKernel::kAvx2, params}};
  auto runs = interleave(reader, setups, frames);
  if (!runs) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", runs.error().c_str());
    return 1;
  }
  std::size_t differing = 0;
  for (auto member : {&Interleaved::labeled, &Interleaved::late}) {
    const volume::LabeledVolume& a = *(runs.value()[0].*member);
    const volume::LabeledVolume& b = *(runs.value()[1].*member);
    differing += differingVoxels(&a.geometryGrid(), &b.geometryGrid()) + differingVoxels(a.colorGrid(), b.colorGrid()) +
                 differingVoxels(a.labelSidecarGrid(), b.labelSidecarGrid());
  }
  Table table = interleavedTable("integration kernels, interleaved frame by frame (median / p95 per frame)", setups,
                                 runs.value());
  table.add("voxels differing (geometry, colour, sidecar)", std::to_string(differing),
            differing == 0 ? "the two maps are bit-identical" : "MISMATCH: the kernels disagree");
  table.print();
  std::printf("load average at the end: %.2f\n", loadAverage());
  return differing == 0 ? 0 : 1;
}

// The evidence rule (the paper's) and the server's default bayes rule with the default kernel,
// interleaved: the cost of the default rule as a ratio measured in one run.
int compareRules(const datasets::SevenScenesReader& reader, const volume::VolumeParams& params, std::size_t frames) {
  std::array<Setup, 2> setups{Setup{"evidence", volume::integrationKernel(), params},
                              Setup{"bayes", volume::integrationKernel(), params}};
  setups[0].params.label_rule = volume::LabelRule::kEvidence;
  setups[1].params.label_rule = volume::LabelRule::kBayes;
  auto runs = interleave(reader, setups, frames);
  if (!runs) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", runs.error().c_str());
    return 1;
  }
  Table table =
      interleavedTable("label rules, interleaved frame by frame (median / p95 per frame)", setups, runs.value());
  const double ratio = runs.value()[1].integrate_cpu.median() / runs.value()[0].integrate_cpu.median();
  table.add("target: bayes <= 1.3x evidence CPU, integrate+labels", "x" + formatNumber(ratio, 2),
            ratio <= 1.3 ? "met" : "MISSED");
  table.print();
  std::printf("load average at the end: %.2f\n", loadAverage());
  return 0;
}

int runVolumeBench(const VolumeBenchOptions& options) {
  keepScratchResident();  // as semfuse-server does, whose work this times
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", reader.error().c_str());
    return 2;
  }
  const std::size_t frames = std::min(options.frames, reader.value().count());
  volume::VolumeParams params;
  params.voxel_size = options.voxel;
  params.truncation = options.truncation;
  auto rule = volume::parseLabelRule(options.label_rule);
  if (!rule) {
    std::fprintf(stderr, "semfuse-bench volume: --label-rule: %s\n", rule.error().c_str());
    return 2;
  }
  params.label_rule = rule.value();
  params.label_classes = 13;  // labelsFromDepthBands: 12 labels + unlabeled
  if (Status valid = params.validate(); !valid) {
    std::fprintf(stderr, "semfuse-bench volume: %s\n", valid.error().c_str());
    return 2;
  }
  if (!options.kernel.empty()) {
    const bool scalar = options.kernel == "scalar";
    if ((!scalar && options.kernel != "avx2") ||
        !volume::setIntegrationKernel(scalar ? volume::IntegrationKernel::kScalar : volume::IntegrationKernel::kAvx2)) {
      std::fprintf(stderr, "semfuse-bench volume: kernel '%s' is not available (scalar, avx2)\n",
                   options.kernel.c_str());
      return 2;
    }
  }
  const PinholeIntrinsics& k = reader.value().intrinsics();
  std::printf(
      "semfuse-bench volume: %zu frames of %s (%dx%d), voxel %.3f m, truncation %.3f m, %d threads, "
      "%s kernel, %s label rule, load average %.2f at start\n",
      frames, options.data.c_str(), k.width, k.height, params.voxel_size, params.truncation,
      static_cast<int>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism)),
      options.compare_kernels ? "scalar vs avx2" : volume::integrationKernelName(volume::integrationKernel()),
      options.compare_rules ? "evidence vs bayes" : volume::labelRuleName(params.label_rule), loadAverage());
  if (options.compare_kernels) return compareKernels(reader.value(), params, frames);
  if (options.compare_rules) return compareRules(reader.value(), params, frames);

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
  Table table("labeled volume (median / p95 per frame; targets beside them)");
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

const bool volume_registered = registerBench(
    "volume", "integration speed and memory of the labeled volume (7-Scenes frames)", [](CLI::App& command) {
      auto options = std::make_shared<VolumeBenchOptions>();
      addMapOptions(command, options->data, options->voxel, options->truncation);
      command.add_option("--frames", options->frames, "frames to integrate (from frame 0)")->capture_default_str();
      command.add_option("--baseline-frames", options->baseline_frames, "frames for the single-thread baseline")
          ->capture_default_str();
      command.add_option("--kernel", options->kernel, "integration kernel: scalar or avx2 (default: widest available)");
      command
          .add_option("--label-rule", options->label_rule, "label fusion: evidence (the paper's), majority or bayes")
          ->capture_default_str();
      command.add_flag("--compare-kernels", options->compare_kernels,
                       "only time the scalar and avx2 kernels interleaved and check that their maps are identical");
      command.add_flag("--compare-rules", options->compare_rules,
                       "only time the evidence and bayes label rules interleaved: the default rule's cost as a ratio");
      return [options] { return runVolumeBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
