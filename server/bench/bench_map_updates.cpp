// semfuse-bench map-updates: what the live mesh costs the server, on 7-Scenes frames as two
// cameras at 30 Hz would bring them (60 frames a second), with update rounds at --rate. The map
// grows frame by frame; every 60/rate frames one MapUpdater round meshes the changed blocks and
// hands them to a sink that counts what would go on the wire. Printed: the rounds' CPU time
// against the frames' integration time and against one core, the round time (frame integrated ->
// update published = waiting for the round + the round), and per round the blocks and bytes sent
// beside the whole mesh's, to show that the bytes follow the change, not the map.
#include <cstdio>
#include <memory>
#include <shared_mutex>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "map_access.hpp"
#include "map_updater.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::bench {
namespace {

struct MapUpdatesOptions {
  std::string data = redkitchenDir().string();
  std::size_t first = 0, last = 499;
  double voxel = 0.02;
  double truncation = 0.08;
  double input_hz = 60.0;   // two cameras at 30 Hz
  double rate = 2.0;        // update rounds per second (the server's default)
  double live_voxel = 0.0;  // the live mesh's voxel (0: the server's default for this map)
};

// The map behind a shared mutex, as the server's Mapper keeps it.
class BenchMap final : public server::MapAccess {
 public:
  explicit BenchMap(const volume::VolumeParams& params) : volume_(params) {}
  void read(const std::function<void(const volume::LabeledVolume&)>& fn) const override {
    std::shared_lock lock(mutex_);
    fn(volume_);
  }
  std::shared_ptr<const volume::LabeledVolume> snapshot() const override {
    std::shared_lock lock(mutex_);
    return std::make_shared<const volume::LabeledVolume>(volume_.deepCopy());
  }
  const LabelLegend& legend() const override { return legend_; }
  volume::LabeledVolume& volume() { return volume_; }

 private:
  mutable std::shared_mutex mutex_;
  volume::LabeledVolume volume_;
  LabelLegend legend_;
};

class CountingSink final : public server::MapUpdater::Sink {
 public:
  bool listening() const override { return true; }
  void publish(const MapUpdate& update) override {
    for (const MeshBlock& block : update.blocks) bytes += block.payloadBytes() + MeshBlock::kFramingBytes;
  }
  std::size_t bytes = 0;
};

// Labels from depth bands (a stand-in for a segmentation: what matters here is that labels vary).
cv::Mat bandLabels(const cv::Mat& depth) {
  cv::Mat labels(depth.size(), CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const float d = depth.at<float>(v, u);
      if (d > 0) labels.at<uint16_t>(v, u) = static_cast<uint16_t>(1 + static_cast<int>(d / 0.3F) % 12);
    }
  return labels;
}

int runMapUpdates(const MapUpdatesOptions& o) {
  auto reader = datasets::SevenScenesReader::open(o.data);
  if (!reader) {
    std::fprintf(stderr, "semfuse-bench map-updates: %s\n", reader.error().c_str());
    return 1;
  }
  volume::VolumeParams params;
  params.voxel_size = o.voxel;
  params.truncation = o.truncation;
  BenchMap map(params);
  CountingSink sink;
  server::MapUpdateConfig config;
  config.rate_hz = o.rate;
  config.voxel_size = o.live_voxel;
  if (Status ok = server::validateMapUpdateConfig(config, o.voxel, o.truncation); !ok) {
    std::fprintf(stderr, "semfuse-bench map-updates: %s\n", ok.error().c_str());
    return 1;
  }
  server::MapUpdater updater(map, config, sink);

  const std::size_t last = std::min(o.last, reader.value().count() - 1);
  const auto frames_per_round = static_cast<std::size_t>(std::max(1.0, o.input_hz / o.rate));
  Timings integrate_cpu, round_cpu, round_wall;
  double integrate_total = 0, rounds_total = 0;
  std::printf("round  frames  mesh blocks  meshed  sent  sent KiB  whole mesh KiB  sent/whole\n");
  std::size_t round = 0;
  for (std::size_t i = o.first; i <= last; ++i) {
    auto frame = reader.value().load(i);
    if (!frame || !frame.value().camera_to_world) {
      std::fprintf(stderr, "semfuse-bench map-updates: frame %zu unreadable or without pose\n", i);
      return 1;
    }
    const Frame& f = frame.value();
    const cv::Mat labels = bandLabels(f.depth);
    const cv::Mat confidence(f.depth.size(), CV_32FC1, cv::Scalar(0.8F));
    CpuStopwatch cpu;
    auto stats =
        volume::integrate(map.volume(), f.depth, f.color, labels, confidence, f.intrinsics, *f.camera_to_world);
    const double integrate_ms = cpu.elapsedMs();
    integrate_cpu.add(integrate_ms);
    integrate_total += integrate_ms;
    if (!stats) {
      std::fprintf(stderr, "semfuse-bench map-updates: frame %zu: %s\n", i, stats.error().c_str());
      return 1;
    }
    const std::size_t done = i - o.first + 1;
    if (done % frames_per_round != 0 && i != last) continue;

    sink.bytes = 0;
    CpuStopwatch round_watch;
    Stopwatch wall;
    const server::MapUpdater::Round r = updater.update();
    round_cpu.add(round_watch.elapsedMs());
    round_wall.add(wall.elapsedMs());
    rounds_total += round_watch.elapsedMs();
    const auto totals = updater.store().totals();
    const double whole = static_cast<double>(totals.payload_bytes + totals.blocks * MeshBlock::kFramingBytes);
    std::printf("%5zu  %6zu  %11zu  %6zu  %4zu  %8.0f  %14.0f  %9.1f%%\n", ++round, done, totals.blocks,
                r.blocks_meshed, r.blocks_sent, static_cast<double>(sink.bytes) / 1024.0, whole / 1024.0,
                whole > 0 ? 100.0 * static_cast<double>(sink.bytes) / whole : 0.0);
  }

  const double frames = static_cast<double>(last - o.first + 1);
  const double input_seconds = frames / o.input_hz;
  const server::MapUpdater::Totals t = updater.totals();
  Table table("map updates on 7-Scenes frames " + std::to_string(o.first) + "-" + std::to_string(last) + " as " +
              formatNumber(o.input_hz, 0) + " frames/s, rounds at " + formatNumber(o.rate, 1) + " Hz, voxel " +
              formatNumber(o.voxel * 100, 1) + " cm, live mesh " +
              formatNumber(o.voxel * config.stride(o.voxel, o.truncation) * 100, 1) + " cm (CPU ms of all threads)");
  table.addMs("integration per frame, CPU ms", integrate_cpu);
  table.addMs("update round, CPU ms", round_cpu);
  table.addMs("update round, wall ms", round_wall, "frame -> update published: up to one period more");
  table.add("update CPU / integration CPU", formatNumber(100.0 * rounds_total / integrate_total, 1) + " %",
            "the live mesh's cost beside the fusion's");
  table.add("update CPU per second of input", formatNumber(100.0 * rounds_total / 1000.0 / input_seconds, 1) + " %",
            "of one core (target <= 10 %)");
  table.add("latency p50 (estimate)", formatNumber(500.0 / o.rate + round_wall.median(), 0) + " ms",
            "half a period + the round's median; DDS delivery not included (target <= 300 ms)");
  table.add(
      "bytes sent per second",
      formatNumber(
          static_cast<double>(t.payload_bytes + t.blocks_sent * MeshBlock::kFramingBytes) / 1024.0 / input_seconds, 0) +
          " KiB/s",
      std::to_string(t.blocks_sent) + " blocks in " + std::to_string(t.updates) + " updates");
  table.add("blocks meshed / sent", std::to_string(t.blocks_meshed) + " / " + std::to_string(t.blocks_sent));
  table.add("load average", formatNumber(loadAverage(), 2));
  table.print();
  return 0;
}

const bool map_updates_registered = registerBench(
    "map-updates", "the live mesh's cost: CPU, round time and bytes against the change (7-Scenes frames)",
    [](CLI::App& command) {
      auto options = std::make_shared<MapUpdatesOptions>();
      addMapOptions(command, options->data, options->voxel, options->truncation);
      command.add_option("--first", options->first, "first frame")->capture_default_str();
      command.add_option("--last", options->last, "last frame")->capture_default_str();
      command.add_option("--input-rate", options->input_hz, "frames per second the cameras bring together")
          ->capture_default_str();
      command.add_option("--rate", options->rate, "update rounds per second")->capture_default_str();
      command
          .add_option("--live-voxel", options->live_voxel, "the live mesh's voxel, metres (0: the server's default)")
          ->capture_default_str();
      return [options] { return runMapUpdates(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
