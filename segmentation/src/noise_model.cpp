#include "semfuse/segmentation/noise_model.hpp"

#include <algorithm>
#include <random>

#include <opencv2/imgproc.hpp>

namespace semfuse::segmentation {
namespace {

// A wrong label for `current`: uniform over the candidates other than `current`.
LabelId wrongLabel(LabelId current, const std::vector<LabelId>& candidates, std::mt19937_64& rng) {
  const bool current_is_candidate = std::find(candidates.begin(), candidates.end(), current) != candidates.end();
  const std::size_t choices = candidates.size() - (current_is_candidate ? 1 : 0);
  std::size_t pick = std::uniform_int_distribution<std::size_t>(0, choices - 1)(rng);
  for (LabelId c : candidates) {
    if (c == current) continue;
    if (pick-- == 0) return c;
  }
  return candidates.front();  // unreachable: choices counts exactly the ids the loop visits
}

void pixelNoise(cv::Mat& labels, cv::Mat& confidence, const NoiseParams& params, std::mt19937_64& rng) {
  std::bernoulli_distribution flip(params.probability);
  for (int r = 0; r < labels.rows; ++r) {
    auto* label = labels.ptr<uint16_t>(r);
    auto* conf = confidence.ptr<float>(r);
    for (int c = 0; c < labels.cols; ++c) {
      if (label[c] == kUnlabeled || !flip(rng)) continue;
      label[c] = wrongLabel(label[c], params.candidates, rng);
      conf[c] = 1.0F;
    }
  }
}

void regionNoise(cv::Mat& labels, cv::Mat& confidence, const NoiseParams& params, std::mt19937_64& rng) {
  const cv::Mat original = labels.clone();
  std::vector<uint16_t> present;
  for (int r = 0; r < original.rows; ++r) {
    const auto* row = original.ptr<uint16_t>(r);
    present.insert(present.end(), row, row + original.cols);
  }
  std::sort(present.begin(), present.end());
  present.erase(std::unique(present.begin(), present.end()), present.end());
  std::bernoulli_distribution flip(params.probability);
  for (uint16_t value : present) {
    if (value == kUnlabeled) continue;
    cv::Mat components;
    const int count = cv::connectedComponents(original == value, components, 4, CV_32S);
    // Component 0 is everything that is not `value`.
    std::vector<int> replacement(count, -1);
    for (int k = 1; k < count; ++k) {
      if (flip(rng)) replacement[k] = wrongLabel(value, params.candidates, rng);
    }
    for (int r = 0; r < labels.rows; ++r) {
      const auto* comp = components.ptr<int32_t>(r);
      auto* label = labels.ptr<uint16_t>(r);
      auto* conf = confidence.ptr<float>(r);
      for (int c = 0; c < labels.cols; ++c) {
        if (comp[c] > 0 && replacement[comp[c]] >= 0) {
          label[c] = static_cast<uint16_t>(replacement[comp[c]]);
          conf[c] = 1.0F;
        }
      }
    }
  }
}

// Renumbers the ids at random and erodes every mask by `erosion` pixels (3x3 steps).
void instanceNoise(cv::Mat& instances, int erosion, std::mt19937_64& rng) {
  std::vector<uint16_t> ids(instances.begin<uint16_t>(), instances.end<uint16_t>());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  ids.erase(std::remove(ids.begin(), ids.end(), uint16_t{0}), ids.end());
  std::vector<uint16_t> renamed(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) renamed[i] = static_cast<uint16_t>(i + 1);
  std::shuffle(renamed.begin(), renamed.end(), rng);
  cv::Mat out = cv::Mat::zeros(instances.size(), CV_16UC1);
  for (std::size_t i = 0; i < ids.size(); ++i) {
    cv::Mat mask = instances == ids[i];
    if (erosion > 0) cv::erode(mask, mask, cv::Mat(), cv::Point(-1, -1), erosion);
    out.setTo(renamed[i], mask);
  }
  instances = out;
}

}  // namespace

Result<NoiseModel> parseNoiseModel(const std::string& text) {
  if (text == "pixel") return NoiseModel::kPixel;
  if (text == "region") return NoiseModel::kRegion;
  return makeError("unknown noise model '" + text + "' (pixel, region)");
}

Result<Segmentation> addLabelNoise(const Segmentation& clean, const NoiseParams& params, uint64_t frame_seq) {
  if (clean.labels.type() != CV_16UC1) return makeError("noise: labels must be CV_16UC1");
  if (params.probability < 0.0 || params.probability > 1.0) return makeError("noise: probability must be in [0, 1]");
  if (params.candidates.size() < 2) return makeError("noise: needs at least two candidate labels");
  if (params.instance_erosion < 0) return makeError("noise: instance erosion must not be negative");
  if (!clean.instances.empty() && (clean.instances.type() != CV_16UC1 || clean.instances.size() != clean.labels.size()))
    return makeError("noise: instances must be CV_16UC1 of the labels' size");
  Segmentation noisy = clean;
  noisy.labels = clean.labels.clone();
  noisy.confidence =
      clean.confidence.empty() ? cv::Mat(clean.labels.size(), CV_32FC1, cv::Scalar(1.0F)) : clean.confidence.clone();
  // One stream per frame: frames are independent, and a rerun reproduces each of them.
  std::seed_seq seq{static_cast<uint32_t>(params.seed), static_cast<uint32_t>(params.seed >> 32),
                    static_cast<uint32_t>(frame_seq), static_cast<uint32_t>(frame_seq >> 32)};
  std::mt19937_64 rng(seq);
  if (params.model == NoiseModel::kPixel) pixelNoise(noisy.labels, noisy.confidence, params, rng);
  else regionNoise(noisy.labels, noisy.confidence, params, rng);
  if (!clean.instances.empty()) {
    noisy.instances = clean.instances.clone();
    instanceNoise(noisy.instances, params.instance_erosion, rng);
  }
  return noisy;
}

}  // namespace semfuse::segmentation
