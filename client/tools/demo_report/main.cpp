// semfuse-demo-report: after a demo run on the synthetic room, measures what label fusion gained.
// For the frames the noisy segmenter labeled, it compares against the ground truth (a) the labels
// the segmenter published (reproduced exactly: the noise is deterministic per seed and frame) and
// (b) the fused map's labels, raycast by the server at the same pose. Writes report.md,
// report.json and a side-by-side image [colour | ground truth | noisy input | fused map].
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>

#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/cli/exit_codes.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/logging.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/segmentation/noise_model.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/wire/image_convert.hpp"

namespace {

struct Options {
  int domain_id = -1;
  int frames = 120;
  int every = 2;
  double noise = 0.3;
  std::string noise_model = "pixel";
  uint64_t seed = 0;
  std::string out = "out/demo";
  double timeout_s = 30.0;
  std::string log_level;
};

struct ViewErrors {
  int frame = 0;
  double per_frame = 0.0;   // noisy input vs ground truth, over ground-truth pixels
  double volumetric = 0.0;  // fused map vs ground truth, over pixels the map labels
  double coverage = 0.0;    // fraction of ground-truth pixels the map labels
};

double mean(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}
uint64_t total(const std::vector<semfuse::client::ReasonCount>& counts) {
  uint64_t sum = 0;
  for (const auto& c : counts) sum += c.count;
  return sum;
}

double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  const double m = mean(v);
  double sum = 0.0;
  for (double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / (v.size() - 1));
}

cv::Mat captioned(const cv::Mat& rgb, const std::string& caption) {
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  cv::Mat framed(bgr.rows + 28, bgr.cols, CV_8UC3, cv::Scalar(255, 255, 255));
  bgr.copyTo(framed(cv::Rect(0, 28, bgr.cols, bgr.rows)));
  cv::putText(framed, caption, {6, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(20, 20, 20), 1, cv::LINE_AA);
  return framed;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace semfuse;
  Options o;
  CLI::App app{
      "semfuse-demo-report: per-frame vs volumetric label error of a demo run on the synthetic room, "
      "with a side-by-side image and a report (markdown + JSON)."};
  app.add_option("--domain-id", o.domain_id, "DDS domain id of the server (default: Cyclone's default)");
  app.add_option("--frames", o.frames, "frames in the synthetic orbit the camera replayed")->capture_default_str();
  app.add_option("--every", o.every, "the segmenter labeled every Nth frame")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--noise", o.noise, "the segmenter's noise probability")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--noise-model", o.noise_model, "pixel or region")->capture_default_str();
  app.add_option("--seed", o.seed, "the segmenter's noise seed")->capture_default_str();
  app.add_option("--out", o.out, "output folder")->capture_default_str();
  app.add_option("--timeout", o.timeout_s, "seconds per query")->capture_default_str();
  app.add_option("--log-level", o.log_level, "log level");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return e.get_exit_code() == 0 ? code : cli::kExitUsage;
  }
  if (Status ok = setupLogging("semfuse-demo-report", o.log_level); !ok) {
    std::fprintf(stderr, "%s\n", ok.error().c_str());
    return cli::kExitUsage;
  }
  auto noise_model = segmentation::parseNoiseModel(o.noise_model);
  if (!noise_model.ok()) {
    spdlog::error("{}", noise_model.error());
    return cli::kExitUsage;
  }

  const auto timeout = std::chrono::milliseconds(static_cast<int64_t>(o.timeout_s * 1000));
  dds::Participant participant(o.domain_id < 0 ? DDS_DOMAIN_DEFAULT : static_cast<dds_domainid_t>(o.domain_id));
  client::MapClient map(participant);
  auto status = map.stats(timeout);
  if (!status.ok()) {
    spdlog::error("server: {}", status.error());
    return cli::kExitTimeout;
  }
  const LabelLegend legend = map.waitForLegend(timeout).value_or(*builtinLegend("synthetic"));

  synthetic::SequenceConfig config;
  config.trajectory.frame_count = o.frames;
  config.room.seed = o.seed;
  config.seed = o.seed;
  synthetic::SyntheticSequence sequence(config);
  segmentation::NoiseParams noise{noise_model.value(), o.noise, o.seed, {}};
  for (const auto& info : legend.labels)
    if (info.id != kUnlabeled && !legend.isBackground(info.id)) noise.candidates.push_back(info.id);

  std::filesystem::create_directories(o.out);
  std::vector<ViewErrors> views;
  const int showcase = (o.frames / 2 / o.every) * o.every;
  for (int i = 0; i < o.frames; i += o.every) {
    auto gt = sequence.frameWithGroundTruth(i);
    if (!gt.ok()) {
      spdlog::error("frame {}: {}", i, gt.error());
      return cli::kExitServerError;
    }
    const auto& [frame, truth] = gt.value();
    auto noisy = segmentation::addLabelNoise(truth, noise, static_cast<uint64_t>(i));
    auto fused = map.raycast(*frame.camera_to_world, frame.intrinsics, client::kLabelsLayer, timeout);
    if (!noisy.ok() || !fused.ok()) {
      spdlog::error("frame {}: {}", i, !noisy.ok() ? noisy.error() : fused.error());
      return fused.ok() ? cli::kExitServerError : cli::kExitTimeout;
    }
    const cv::Mat& t = truth.labels;
    const cv::Mat& n = noisy.value().labels;
    const cv::Mat& f = fused.value().labels;
    long truth_pixels = 0, noisy_wrong = 0, fused_pixels = 0, fused_wrong = 0;
    for (int v = 0; v < t.rows; ++v)
      for (int u = 0; u < t.cols; ++u) {
        const uint16_t expected = t.at<uint16_t>(v, u);
        if (expected == kUnlabeled) continue;
        ++truth_pixels;
        noisy_wrong += n.at<uint16_t>(v, u) != expected;
        if (f.at<uint16_t>(v, u) == kUnlabeled) continue;
        ++fused_pixels;
        fused_wrong += f.at<uint16_t>(v, u) != expected;
      }
    if (truth_pixels == 0) continue;
    views.push_back({i, static_cast<double>(noisy_wrong) / truth_pixels,
                     fused_pixels ? static_cast<double>(fused_wrong) / fused_pixels : 1.0,
                     static_cast<double>(fused_pixels) / truth_pixels});
    if (i == showcase) {
      cv::Mat row;
      cv::hconcat(std::vector<cv::Mat>{captioned(frame.color, "camera colour (frame " + std::to_string(i) + ")"),
                                       captioned(wire::colorizeLabels(t, legend), "ground truth"),
                                       captioned(wire::colorizeLabels(n, legend),
                                                 "segmenter input (" + std::to_string(static_cast<int>(o.noise * 100)) +
                                                     "% noise)"),
                                       captioned(wire::colorizeLabels(f, legend), "fused map (raycast)")},
                  row);
      cv::imwrite((std::filesystem::path(o.out) / "labels_side_by_side.png").string(), row);
    }
  }
  if (views.empty()) {
    spdlog::error("no frame with ground truth to evaluate");
    return cli::kExitServerError;
  }

  std::vector<double> per_frame, volumetric, coverage;
  for (const auto& v : views) {
    per_frame.push_back(v.per_frame);
    volumetric.push_back(v.volumetric);
    coverage.push_back(v.coverage);
  }
  const auto& s = status.value();
  const std::filesystem::path md_path = std::filesystem::path(o.out) / "report.md";
  std::ofstream md(md_path);
  md << "# semfuse demo report\n\n"
     << "Synthetic room, " << o.frames << " frames with poses; segmenter: ground truth with " << o.noise * 100 << "% "
     << o.noise_model << " noise (seed " << o.seed << "), every " << o.every << " frame(s), published late.\n\n"
     << "| | value |\n|---|---|\n"
     << "| frames received / integrated / lost | " << s.frames_received << " / " << s.frames_integrated << " / "
     << s.frames_lost << " |\n"
     << "| segmentations received / integrated | " << s.segmentations_received << " / " << s.segmentations_integrated
     << " |\n"
     << "| frames dropped / rejected (all reasons) | " << total(s.dropped) << " / " << total(s.rejected) << " |\n"
     << "| map | " << s.allocated_voxels << " voxels in " << s.allocated_blocks << " blocks, "
     << fmt::format("{:.1f}", s.map_bytes / (1024.0 * 1024.0)) << " MiB, voxel " << s.voxel_size << " m |\n"
     << "| views evaluated | " << views.size() << " |\n"
     << fmt::format("| per-frame label error (segmenter input) | {:.2f}% ± {:.2f} |\n", 100 * mean(per_frame),
                    100 * stddev(per_frame))
     << fmt::format("| volumetric label error (fused map) | {:.2f}% ± {:.2f} |\n", 100 * mean(volumetric),
                    100 * stddev(volumetric))
     << fmt::format("| map coverage of labeled pixels | {:.1f}% |\n\n", 100 * mean(coverage))
     << "Errors are fractions of ground-truth-labeled pixels whose label differs from the ground truth, "
        "at the poses of the segmented frames; the volumetric error counts pixels the map labels.\n";
  std::ofstream json(std::filesystem::path(o.out) / "report.json");
  json << "{\n  \"frames\": " << o.frames << ",\n  \"frames_integrated\": " << s.frames_integrated
       << ",\n  \"segmentations_integrated\": " << s.segmentations_integrated << ",\n  \"noise\": " << o.noise
       << ",\n  \"noise_model\": \"" << o.noise_model << "\",\n  \"views\": " << views.size()
       << ",\n  \"per_frame_error\": " << mean(per_frame) << ",\n  \"per_frame_error_std\": " << stddev(per_frame)
       << ",\n  \"volumetric_error\": " << mean(volumetric) << ",\n  \"volumetric_error_std\": " << stddev(volumetric)
       << ",\n  \"coverage\": " << mean(coverage) << ",\n  \"map_bytes\": " << s.map_bytes
       << ",\n  \"allocated_voxels\": " << s.allocated_voxels << "\n}\n";
  spdlog::info("per-frame error {:.1f}%, volumetric error {:.1f}% over {} views; report in {}", 100 * mean(per_frame),
               100 * mean(volumetric), views.size(), md_path.string());
  return cli::kExitOk;
}
