#pragma once
// Label legends from YAML files, and validation of any legend (built-in, file or wire).
//
//   name: kitchen
//   labels:
//     - {id: 0, name: unlabeled, color: [0, 0, 0]}
//     - {id: 1, name: wall, color: [120, 120, 120]}
//   background: [0]          # optional: ids that never change a voxel's label
#include <filesystem>
#include <string>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse {

// Labels sorted by unique id with unique, non-empty names; background ids sorted, unique and labels.
Status validateLegend(const LabelLegend& legend);

// `source` names the text in error messages (a file name, "<string>").
Result<LabelLegend> parseLegendYaml(const std::string& text, const std::string& source = "<string>");
Result<LabelLegend> loadLegendYaml(const std::filesystem::path& file);
// A built-in legend name ("ade20k", ...) or else a YAML file path.
Result<LabelLegend> resolveLegend(const std::string& name_or_file);
// The YAML form that parseLegendYaml reads back.
std::string legendToYaml(const LabelLegend& legend);

}  // namespace semfuse
