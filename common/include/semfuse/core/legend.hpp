#pragma once
// Label legend: which label ids exist, their names and display colours, and which of them
// are "background" (never change a voxel's label, as in the paper).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace semfuse {

using LabelId = uint16_t;
inline constexpr LabelId kUnlabeled = 0;

struct LabelInfo {
  LabelId id = 0;
  std::string name;
  std::array<uint8_t, 3> rgb{0, 0, 0};
};

struct LabelLegend {
  std::string name;
  std::vector<LabelInfo> labels;        // sorted by id, unique ids
  std::vector<LabelId> background_ids;  // sorted

  bool contains(LabelId id) const;
  bool isBackground(LabelId id) const;
  const LabelInfo* find(LabelId id) const;
  // Display colour of a label; a deterministic colour for ids missing from the legend.
  std::array<uint8_t, 3> colorOf(LabelId id) const;
  LabelId maxId() const { return labels.empty() ? 0 : labels.back().id; }
};

// Built-in legends: "ade20k" (150 classes + 0 other), "voc" (21), "nyu40" (40 + 0),
// "synthetic" (the labels of the built-in synthetic scene). Unknown name: nullopt.
std::optional<LabelLegend> builtinLegend(const std::string& name);
std::vector<std::string> builtinLegendNames();

}  // namespace semfuse
