#include "semfuse/volume/volume_params.hpp"

#include <string>
#include <type_traits>

#include "semfuse/core/number_text.hpp"
#include "semfuse/volume/volume_param_table.hpp"

namespace semfuse::volume {

Status VolumeParams::validate() const {
  Status status;
  forEachVolumeParam(*this, [&status](const ParamField& field, const auto& value) {
    using T = std::decay_t<decltype(value)>;
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      if (status.ok()) status = checkParam(field, static_cast<double>(value));
    }
  });
  if (!status) return status;
  // What one field's range cannot say.
  if (truncation < voxel_size)
    return invalidArgument("truncation must be at least one voxel (" + numberText(voxel_size) + " m), got " +
                           numberText(truncation));
  // Half floats store the TSDF: beyond ~65504 they overflow; far earlier the band is absurd.
  if (truncation > 1000.0 * voxel_size)
    return invalidArgument("truncation " + numberText(truncation) + " m is more than 1000 voxels wide");
  if (label_likelihood <= 1.0f / static_cast<float>(label_classes))
    return invalidArgument("label_likelihood must be above chance (1/label_classes = " +
                           numberText(1.0 / label_classes) + "), got " + numberText(label_likelihood));
  if (max_depth <= min_depth)
    return invalidArgument("depth range must satisfy min_depth < max_depth, got [" + numberText(min_depth) + ", " +
                           numberText(max_depth) + "]");
  return Status::Ok();
}

LabelRuleConfig VolumeParams::labelRuleConfig() const {
  LabelRuleConfig config;
  config.rule = label_rule;
  config.max_score = max_label_score;
  config.label_classes = static_cast<float>(label_classes);
  config.likelihood = label_likelihood;
  config.full_confidence_log_ratio = bayesLogRatio(1.0f, config.label_classes, config.likelihood);
  if (label_rule == LabelRule::kBayes) config.bayes_increments = tabulateBayesIncrements(config);
  return config;
}

}  // namespace semfuse::volume
