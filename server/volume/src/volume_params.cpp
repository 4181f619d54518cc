#include "semfuse/volume/volume_params.hpp"

#include <sstream>
#include <string>
#include <type_traits>

#include "semfuse/volume/volume_param_table.hpp"

namespace semfuse::volume {
namespace {
std::string number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}
Error invalid(std::string message) { return makeError(ErrorCode::kInvalidArgument, std::move(message)); }
}  // namespace

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
    return invalid("truncation must be at least one voxel (" + number(voxel_size) + " m), got " + number(truncation));
  // Half floats store the TSDF: beyond ~65504 they overflow; far earlier the band is absurd.
  if (truncation > 1000.0 * voxel_size)
    return invalid("truncation " + number(truncation) + " m is more than 1000 voxels wide");
  if (label_likelihood <= 1.0f / static_cast<float>(label_classes))
    return invalid("label_likelihood must be above chance (1/label_classes = " + number(1.0 / label_classes) +
                   "), got " + number(label_likelihood));
  if (max_depth <= min_depth)
    return invalid("depth range must satisfy min_depth < max_depth, got [" + number(min_depth) + ", " +
                   number(max_depth) + "]");
  return Status::Ok();
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
