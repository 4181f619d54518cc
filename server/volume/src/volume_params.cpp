#include "semfuse/volume/volume_params.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace semfuse::volume {
namespace {
// Largest value a half float holds with integer resolution; weights and scores are halves.
constexpr float kHalfExactIntegerLimit = 2048.0f;

std::string num(double v) { return std::to_string(v); }
}  // namespace

Status VolumeParams::validate() const {
  if (!std::isfinite(voxel_size) || voxel_size <= 0.0)
    return makeError("voxel_size must be a finite positive number of metres, got " + num(voxel_size));
  if (!std::isfinite(truncation) || truncation < voxel_size)
    return makeError("truncation must be finite and at least one voxel (" + num(voxel_size) + " m), got " +
                     num(truncation));
  // Half floats store the TSDF: beyond ~65504 they overflow; far earlier the band is absurd.
  if (truncation > 1000.0 * voxel_size)
    return makeError("truncation " + num(truncation) + " m is more than 1000 voxels wide");
  if (!std::isfinite(max_weight) || max_weight < 1.0f || max_weight > kHalfExactIntegerLimit)
    return makeError("max_weight must be in [1, 2048] (stored as half float), got " + num(max_weight));
  if (!std::isfinite(max_label_score) || max_label_score <= 0.0f || max_label_score > kHalfExactIntegerLimit)
    return makeError("max_label_score must be in (0, 2048] (stored as half float), got " + num(max_label_score));
  if (label_classes < 2 || label_classes > 65535)
    return makeError("label_classes must be in [2, 65535], got " + std::to_string(label_classes));
  if (!std::isfinite(label_likelihood) || label_likelihood <= 1.0f / static_cast<float>(label_classes) ||
      label_likelihood >= 1.0f)
    return makeError("label_likelihood must be above chance (1/label_classes) and below 1, got " +
                     num(label_likelihood));
  if (!std::isfinite(min_depth) || !std::isfinite(max_depth) || min_depth <= 0.0f || max_depth <= min_depth)
    return makeError("depth range must satisfy 0 < min_depth < max_depth, got [" + num(min_depth) + ", " +
                     num(max_depth) + "]");
  return Status::Ok();
}

bool VolumeParams::isBackground(LabelId label) const {
  return std::find(background_labels.begin(), background_labels.end(), label) != background_labels.end();
}

LabelRuleConfig VolumeParams::labelRuleConfig() const {
  LabelRuleConfig config;
  config.rule = label_rule;
  config.max_score = max_label_score;
  config.label_classes = static_cast<float>(label_classes);
  config.likelihood = label_likelihood;
  config.full_confidence_log_ratio = bayesLogRatio(1.0f, config.label_classes, config.likelihood);
  return config;
}

}  // namespace semfuse::volume
