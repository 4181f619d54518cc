#include "semfuse/core/legend.hpp"

#include <algorithm>

namespace semfuse {

const LabelInfo* LabelLegend::find(LabelId id) const {
  auto it = std::lower_bound(labels.begin(), labels.end(), id,
                             [](const LabelInfo& info, LabelId value) { return info.id < value; });
  return (it != labels.end() && it->id == id) ? &*it : nullptr;
}

bool LabelLegend::contains(LabelId id) const { return find(id) != nullptr; }

bool LabelLegend::isBackground(LabelId id) const {
  return std::binary_search(background_ids.begin(), background_ids.end(), id);
}

std::array<uint8_t, 3> LabelLegend::colorOf(LabelId id) const {
  if (const LabelInfo* info = find(id)) return info->rgb;
  // Ids outside the legend get a stable, well-spread colour (golden-ratio hue walk) so that
  // two unknown labels are still told apart in an image.
  const float hue = static_cast<float>(id) * 0.618034f;
  const float h = (hue - static_cast<int>(hue)) * 6.0f;
  const int sector = static_cast<int>(h);
  const float f = h - sector;
  const uint8_t hi = 230, lo = 60;
  const auto mid = static_cast<uint8_t>(lo + (hi - lo) * f);
  const auto mid_inv = static_cast<uint8_t>(hi - (hi - lo) * f);
  switch (sector % 6) {
    case 0:
      return {hi, mid, lo};
    case 1:
      return {mid_inv, hi, lo};
    case 2:
      return {lo, hi, mid};
    case 3:
      return {lo, mid_inv, hi};
    case 4:
      return {mid, lo, hi};
    default:
      return {hi, lo, mid_inv};
  }
}

}  // namespace semfuse
