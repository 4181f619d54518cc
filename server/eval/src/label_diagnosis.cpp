#include "label_diagnosis.hpp"

#include <algorithm>

#include "semfuse/volume/integrator.hpp"

namespace semfuse::eval {
Result<ExactCounts> countLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                const LabelSource& source) {
  const EvalSequence& sequence = scenario.sequence();
  std::vector<Segmentation> frames;
  ExactCounts exact;
  for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
    auto labels = labelsFor(sequence, i, source);
    if (!labels) return makeError(labels.error());
    frames.push_back(std::move(labels).value());
  }
  exact.labels = sequence.present_labels;
  const auto& surface = scenario.surface();
  exact.counts.assign(surface.size() * exact.labels.size(), 0.0f);

  volume::VolumeParams counting = params;
  counting.label_rule = volume::LabelRule::kMajority;
  counting.max_label_score = 2048.0f;  // above any count of these sequences: no clamp shift
  counting.background_labels.clear();
  for (std::size_t l = 0; l < exact.labels.size(); ++l) {
    volume::LabeledVolume volume = withLabelRule(scenario.geometry(), counting);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const cv::Mat shown = frames[i].labels == exact.labels[l];  // 255 where shown label l
      cv::Mat binary;
      shown.convertTo(binary, CV_16UC1, 1.0 / 255.0);
      const EvalFrame& frame = sequence.frames[i];
      auto stats =
          volume::integrateLabels(volume, frame.depth, binary, cv::Mat(), sequence.intrinsics, frame.camera_to_world);
      if (!stats) return makeError(stats.error());
    }
    for (std::size_t v = 0; v < surface.size(); ++v) {
      const volume::VoxelValue value = volume.voxel(surface[v]);
      if (value.label == 1) exact.counts[v * exact.labels.size() + l] = value.score;
    }
  }
  return exact;
}

Result<LabelDiagnosis> diagnoseLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                      const LabelSource& source) {
  auto clean = countLabels(scenario, params, LabelSource{});
  if (!clean) return makeError(clean.error());
  auto noisy = countLabels(scenario, params, source);
  if (!noisy) return makeError(noisy.error());
  return diagnoseLabels(scenario, params, source, clean.value(), noisy.value());
}

Result<LabelDiagnosis> diagnoseLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                      const LabelSource& source, const ExactCounts& clean, const ExactCounts& noisy) {
  const EvalSequence& sequence = scenario.sequence();
  volume::LabeledVolume reference = withLabelRule(scenario.geometry(), params);
  if (auto cost = fuseLabels(reference, sequence, LabelSource{}); !cost) return makeError(cost.error());
  volume::LabeledVolume fused = withLabelRule(scenario.geometry(), params);
  if (auto cost = fuseLabels(fused, sequence, source); !cost) return makeError(cost.error());
  if (clean.labels != noisy.labels || clean.counts.size() != scenario.surface().size() * clean.labels.size() ||
      noisy.counts.size() != clean.counts.size())
    return makeError("exact counts of another scenario");

  const std::vector<int>& bounds = observationBins();
  LabelDiagnosis d;
  for (int lower : bounds) d.bins.push_back({lower});
  const std::size_t labels = clean.labels.size();
  const auto& surface = scenario.surface();
  for (std::size_t v = 0; v < surface.size(); ++v) {
    const LabelId truth = reference.voxel(surface[v]).label;
    if (truth == kUnlabeled) continue;  // the metric skips what the reference does not label
    const float* shown = noisy.of(v);
    const float* shown_clean = clean.of(v);
    float observations = 0.0f, clean_total = 0.0f, clean_top = 0.0f, truth_count = 0.0f, rival = 0.0f;
    for (std::size_t l = 0; l < labels; ++l) {
      observations += shown[l];
      clean_total += shown_clean[l];
      clean_top = std::max(clean_top, shown_clean[l]);
      if (noisy.labels[l] == truth) truth_count = shown[l];
      else rival = std::max(rival, shown[l]);
    }
    const bool rule_wrong = fused.voxel(surface[v]).label != truth;
    const bool oracle_wrong = !(truth_count > rival);
    const bool border = clean_top < kBorderShare * clean_total;
    const auto bin = static_cast<std::size_t>(
        std::upper_bound(bounds.begin(), bounds.end(), static_cast<int>(observations)) - bounds.begin() - 1);
    DiagnosisBin& b = d.bins[bin];
    ++b.voxels, ++d.voxels;
    b.rule_wrong += rule_wrong, d.rule_wrong += rule_wrong;
    b.oracle_wrong += oracle_wrong, d.oracle_wrong += oracle_wrong;
    d.border_voxels += border;
    d.border_rule_wrong += border && rule_wrong;
    d.rule_only_wrong += rule_wrong && !oracle_wrong;
    d.oracle_only_wrong += oracle_wrong && !rule_wrong;
  }
  return d;
}

}  // namespace semfuse::eval
