// semfuse-segmenter: segments the frames on rt/semfuse/frames with a chosen backend and publishes
// the labels on rt/semfuse/segmentations.
#include <chrono>
#include <thread>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include "backend_factory.hpp"
#include "semfuse/cli/command_line.hpp"
#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/cli/stop_signal.hpp"
#include "semfuse/client/segmenter.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/participant.hpp"

namespace {

using namespace semfuse;

struct Options {
  cli::CommonOptions common;
  tools::BackendOptions backend;
  client::SegmenterOptions segmenter;
  int delay_ms = 0;
  double duration_s = 0.0;
  double idle_exit_s = 0.0;
  double report_s = 5.0;
};

void addOptions(CLI::App& app, Options& o) {
  auto& b = o.backend;
  app.add_option("--backend", b.backend, "gt (ground truth), dnn (OpenCV dnn model) or noise (corrupts --base)")
      ->check(CLI::IsMember({"gt", "dnn", "noise"}))
      ->capture_default_str();
  app.add_option("--base", b.base, "noise: the backend whose labels are corrupted")
      ->check(CLI::IsMember({"gt", "dnn"}))
      ->capture_default_str();
  app.add_option("--labels-dir", b.labels_dir, "gt: folder of label images (default: the synthetic room's labels)");
  app.add_option("--labels-pattern", b.labels_pattern, "gt: label file name for a frame seq, fmt-style")
      ->capture_default_str();
  app.add_flag("--instances", b.instances,
               "gt: send the synthetic room's exact instance map too, as a panoptic segmenter would");
  app.add_option("--instance-erosion", b.instance_erosion,
                 "noise: pixels taken off every instance mask's border (ids are renumbered every frame)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--noise-model", b.noise_model, "noise: pixel (independent pixels) or region (whole regions)")
      ->check(CLI::IsMember({"pixel", "region"}))
      ->capture_default_str();
  app.add_option("--noise", b.noise, "noise: probability p that a pixel/region gets a wrong label")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--seed", b.seed, "noise: random seed")->capture_default_str();
  app.add_option("--legend", b.legend, "noise: legend (built-in name or YAML file) whose labels are drawn")
      ->capture_default_str();
  app.add_option("--noise-labels", b.noise_labels, "noise: explicit label ids to draw from (instead of --legend)");
  app.add_option("--model", b.model, "dnn: TensorFlow .pb or ONNX model file");
  app.add_option("--input-size", b.input_size, "dnn: network input WIDTH HEIGHT")->expected(2)->capture_default_str();
  app.add_option("--layout", b.layout, "dnn: tensor layout of input and logits")
      ->check(CLI::IsMember({"nchw", "nhwc"}))
      ->capture_default_str();
  app.add_option("--mean", b.mean, "dnn: normalisation (x - mean) * scale")->capture_default_str();
  app.add_option("--scale", b.scale, "dnn: normalisation (x - mean) * scale")->capture_default_str();
  app.add_option("--output-name", b.output_name, "dnn: output layer (default: the last)");
  app.add_option("--label-map", b.label_map, "dnn: file of 'model_class legend_id' lines (default: identity)");
  app.add_option("--segmenter-id", o.segmenter.segmenter_id, "id published with each segmentation")
      ->capture_default_str();
  app.add_option("--camera-id", o.segmenter.camera_id, "only frames of this camera (default: all)");
  app.add_option("--every", o.segmenter.every, "segment every Nth frame")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--queue", o.segmenter.queue,
                 "frames kept while the model is busy, oldest given up first (1: the newest only; a replay that "
                 "must label every frame: as many as it sends)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{4096}))
      ->capture_default_str();
  app.add_option("--delay", o.delay_ms, "milliseconds to hold each result before publishing")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--idle-exit", o.idle_exit_s,
                 "stop when no frame came for this many seconds after the first one (0 = never)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--report", o.report_s, "seconds between statistics lines")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cli::addCommonOptions(app, o.common);
}

void report(const client::SegmenterStats& s) {
  spdlog::info(
      "frames received {}, segmented {}, published {}, skipped {} (newer frame), not selected {}, "
      "failed {}; {:.1f} ms per frame (last {:.1f} ms)",
      s.received, s.segmented, s.published, s.skipped, s.not_selected, s.failed, s.meanSegmentMs(), s.last_segment_ms);
}

int run(Options& o) {
  auto function = tools::makeSegmentFunction(o.backend);
  if (!function) {
    spdlog::error("{}", function.error());
    return cli::kExitFailure;
  }
  o.segmenter.delay = std::chrono::milliseconds(o.delay_ms);
  dds::Participant participant(o.common.domain_id < 0 ? DDS_DOMAIN_DEFAULT
                                                      : static_cast<dds_domainid_t>(o.common.domain_id));
  client::Segmenter segmenter(participant, std::move(function).value(), o.segmenter);
  segmenter.start();
  spdlog::info("{} backend{} running as '{}', every {} frame(s), delay {} ms", o.backend.backend,
               o.backend.backend == "noise" ? " over " + o.backend.base : std::string(), o.segmenter.segmenter_id,
               o.segmenter.every, o.delay_ms);

  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto last_report = start;
  auto last_activity = start;
  uint64_t last_received = 0;
  while (!cli::stopRequested()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const auto now = Clock::now();
    const auto stats = segmenter.stats();
    if (stats.received != last_received) {
      last_received = stats.received;
      last_activity = now;
    }
    if (now - last_report >= std::chrono::duration<double>(o.report_s)) {
      report(stats);
      last_report = now;
    }
    if (o.duration_s > 0 && now - start >= std::chrono::duration<double>(o.duration_s)) break;
    if (o.idle_exit_s > 0 && stats.received > 0 &&
        now - last_activity >= std::chrono::duration<double>(o.idle_exit_s)) {
      spdlog::info("no frame for {} s: stopping", o.idle_exit_s);
      break;
    }
  }
  segmenter.stop();
  if (Status acked = segmenter.waitForAcknowledgements(std::chrono::seconds(5)); !acked) {
    spdlog::warn("{}", acked.error());
  }
  report(segmenter.stats());
  return cli::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Segments the frames a semfuse server receives and publishes their labels.", "semfuse-segmenter"};
  Options options;
  addOptions(app, options);
  if (const int code = cli::parseCommandLine(app, argc, argv); code >= 0) return code;
  if (Status s = setupLogging("semfuse-segmenter", options.common.log_level); !s) {
    spdlog::error("{}", s.error());
    return cli::kExitUsage;
  }
  cli::installStopHandler();
  try {
    return run(options);
  } catch (const dds::DdsError& e) {
    spdlog::error("DDS: {}", e.what());
    return cli::kExitFailure;
  }
}
