#include "semfuse/tracking/keyframe_store.hpp"

#include <algorithm>
#include <random>

namespace semfuse::tracking {
namespace {

// The fern tests read the coarsest small image (40x30 of a 640x480 frame): blurred enough by
// the downsampling that a few pixels of motion change few outcomes.
constexpr int kCodeLevel = ImagePyramid::kLevels - 1;

}  // namespace

KeyframeStore::KeyframeStore(KeyframeParams params) : params_(params) {
  params_.ferns = std::max(params_.ferns, 1);
  params_.tests_per_fern = std::clamp(params_.tests_per_fern, 1, 8);
  std::mt19937_64 rng(params_.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  // Positions are drawn in normalised image coordinates and resolved per image, so one set of
  // ferns serves any resolution.
  tests_.resize(static_cast<std::size_t>(params_.ferns) * static_cast<std::size_t>(params_.tests_per_fern));
  for (Test& test : tests_) {
    test.level = kCodeLevel;
    test.x = static_cast<int>(unit(rng) * 1e6f);
    test.y = static_cast<int>(unit(rng) * 1e6f);
    test.depth = unit(rng) < 0.5f;
    test.threshold = test.depth ? 0.5f + 3.5f * unit(rng) : 0.1f + 0.8f * unit(rng);
  }
  inverted_.assign(static_cast<std::size_t>(params_.ferns),
                   std::vector<std::vector<uint32_t>>(std::size_t{1} << params_.tests_per_fern));
}

std::vector<uint8_t> KeyframeStore::encode(const ImagePyramid& images) const {
  std::vector<uint8_t> code(static_cast<std::size_t>(params_.ferns), 0);
  if (images.empty()) return code;
  const ImageLevel& level = images.level(kCodeLevel);
  const int cols = level.depth.cols, rows = level.depth.rows;
  const bool intensity = !level.intensity.empty();
  for (int f = 0; f < params_.ferns; ++f) {
    uint8_t outcome = 0;
    for (int t = 0; t < params_.tests_per_fern; ++t) {
      const Test& test = tests_[static_cast<std::size_t>(f) * static_cast<std::size_t>(params_.tests_per_fern) +
                                static_cast<std::size_t>(t)];
      const int x = static_cast<int>(static_cast<int64_t>(test.x) * cols / 1000000);
      const int y = static_cast<int>(static_cast<int64_t>(test.y) * rows / 1000000);
      float value = 0.0f;
      if (test.depth) {
        value = level.depth.at<float>(y, x);
      } else if (intensity) {
        value = level.intensity.at<float>(y, x);
      }
      outcome = static_cast<uint8_t>(outcome | ((value > test.threshold ? 1u : 0u) << t));
    }
    code[static_cast<std::size_t>(f)] = outcome;
  }
  return code;
}

std::vector<int> KeyframeStore::agreementCounts(const std::vector<uint8_t>& code) const {
  std::vector<int> counts(keyframes_.size(), 0);
  for (std::size_t f = 0; f < inverted_.size() && f < code.size(); ++f)
    for (uint32_t index : inverted_[f][code[f]]) ++counts[index];
  return counts;
}

bool KeyframeStore::addIfNovel(const std::string& camera_id, const Pose& camera_to_world, const ImagePyramid& images) {
  if (images.empty() || keyframes_.size() >= params_.max_keyframes) return false;
  std::vector<uint8_t> code = encode(images);
  const std::vector<int> counts = agreementCounts(code);
  const int best = counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
  const double dissimilarity = 1.0 - static_cast<double>(best) / static_cast<double>(params_.ferns);
  if (!keyframes_.empty() && dissimilarity < params_.novelty) return false;
  const auto index = static_cast<uint32_t>(keyframes_.size());
  for (std::size_t f = 0; f < code.size(); ++f) inverted_[f][code[f]].push_back(index);
  // Its own copy of the coarse levels: the caller's pyramid is rebuilt in place for later frames.
  keyframes_.push_back({camera_id, camera_to_world, images.cloneFrom(1), std::move(code)});
  return true;
}

std::vector<KeyframeMatch> KeyframeStore::nearest(const std::vector<uint8_t>& code, std::size_t count) const {
  const std::vector<int> counts = agreementCounts(code);
  std::vector<KeyframeMatch> matches;
  matches.reserve(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i)
    matches.push_back({i, static_cast<double>(counts[i]) / static_cast<double>(params_.ferns)});
  const std::size_t keep = std::min(count, matches.size());
  std::partial_sort(matches.begin(), matches.begin() + static_cast<std::ptrdiff_t>(keep), matches.end(),
                    [](const KeyframeMatch& a, const KeyframeMatch& b) { return a.similarity > b.similarity; });
  matches.resize(keep);
  return matches;
}

void KeyframeStore::clear() {
  keyframes_.clear();
  for (auto& fern : inverted_)
    for (auto& list : fern) list.clear();
}

}  // namespace semfuse::tracking
