// semfuse_synthetic_labels: writes, for each frame of a synthetic run, the labels of the demo's
// noisy ground-truth segmenter as a 16-bit PNG (labels-000000.png, ...). Two segmenters that read
// them (semfuse-segmenter --backend gt --labels-dir, a Python one with cv2.imread) publish the same
// labels, so the maps they give can be compared. The noise is the demo's (pixel model, the
// legend's non-background labels, deterministic per seed and frame), which is what
// semfuse-demo-report --noise --seed reproduces to measure the per-frame error.
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>

#include "semfuse/core/legend.hpp"
#include "semfuse/segmentation/noise_model.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"

int main(int argc, char** argv) {
  using namespace semfuse;
  int frames = 60;
  double noise = 0.3;
  uint64_t seed = 7;
  std::string out;
  CLI::App app{"semfuse_synthetic_labels: the demo segmenter's noisy labels of a synthetic run, as PNG files"};
  app.add_option("--frames", frames, "frames in the synthetic orbit")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--noise", noise, "probability that a pixel gets a wrong label")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  app.add_option("--seed", seed, "room and noise seed, as semfuse-demo-report --seed")->capture_default_str();
  app.add_option("--out", out, "folder for labels-NNNNNN.png")->required();
  CLI11_PARSE(app, argc, argv);

  const LabelLegend legend = *builtinLegend("synthetic");
  synthetic::SequenceConfig config;
  config.trajectory.frame_count = frames;
  config.room.seed = seed;
  config.seed = seed;
  synthetic::SyntheticSequence sequence(config);
  segmentation::NoiseParams params{segmentation::NoiseModel::kPixel, noise, seed, {}};
  for (const auto& info : legend.labels)
    if (info.id != kUnlabeled && !legend.isBackground(info.id)) params.candidates.push_back(info.id);

  std::filesystem::create_directories(out);
  for (int i = 0; i < frames; ++i) {
    auto gt = sequence.frameWithGroundTruth(i);
    if (!gt) {
      std::fprintf(stderr, "frame %d: %s\n", i, gt.error().c_str());
      return 1;
    }
    auto noisy = segmentation::addLabelNoise(gt.value().second, params, static_cast<uint64_t>(i));
    if (!noisy) {
      std::fprintf(stderr, "frame %d: %s\n", i, noisy.error().c_str());
      return 1;
    }
    char name[32];
    std::snprintf(name, sizeof name, "labels-%06d.png", i);
    if (!cv::imwrite((std::filesystem::path(out) / name).string(), noisy.value().labels)) {
      std::fprintf(stderr, "cannot write %s in %s\n", name, out.c_str());
      return 1;
    }
  }
  return 0;
}
