#include "semfuse/volume/volume_param_table.hpp"

#include <cmath>
#include <sstream>
#include <type_traits>

#include "semfuse/core/number_text.hpp"

namespace semfuse::volume {

bool ParamRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above = low_open ? value > low : value >= low;
  const bool below = high_open ? value < high : value <= high;
  return above && below;
}

std::string ParamRange::text() const {
  if (std::isinf(high)) return (low_open ? "> " : ">= ") + numberText(low);
  return std::string("in ") + (low_open ? "(" : "[") + numberText(low) + ", " + numberText(high) +
         (high_open ? ")" : "]");
}

Status checkParam(const ParamField& field, double value) {
  if (!field.range || field.range->contains(value)) return Status::Ok();
  return makeError(ErrorCode::kInvalidArgument, std::string(field.key) + " must be a finite number " +
                                                    field.range->text() + ", got " + numberText(value));
}

std::string volumeParamsText(const VolumeParams& params) {
  std::ostringstream out;
  forEachVolumeParam(params, [&out](const ParamField& field, const auto& value) {
    using T = std::decay_t<decltype(value)>;
    if (out.tellp() > 0) out << ' ';
    out << field.key << '=';
    if constexpr (std::is_same_v<T, LabelRule>) {
      out << labelRuleName(value);
    } else if constexpr (std::is_same_v<T, std::vector<LabelId>>) {
      out << '[';
      for (std::size_t i = 0; i < value.size(); ++i) out << (i ? " " : "") << value[i];
      out << ']';
    } else if constexpr (std::is_same_v<T, bool>) {
      out << (value ? "true" : "false");
    } else {
      out << value;
    }
  });
  return out.str();
}

}  // namespace semfuse::volume
