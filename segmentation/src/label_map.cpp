#include "semfuse/segmentation/label_map.hpp"

#include <fstream>
#include <limits>
#include <sstream>

namespace semfuse::segmentation {

LabelMap identityLabelMap(int class_count) {
  LabelMap map(static_cast<std::size_t>(class_count));
  for (int i = 0; i < class_count; ++i) map[i] = static_cast<LabelId>(i);
  return map;
}

Result<LabelMap> parseLabelMap(const std::string& text, int class_count, const std::string& source) {
  LabelMap map(static_cast<std::size_t>(class_count), kUnlabeled);
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    long from = 0;
    long to = 0;
    if (!(fields >> from)) continue;  // blank or comment-only line
    std::string rest;
    if (!(fields >> to) || (fields >> rest)) {
      return makeError(source + ":" + std::to_string(number) + ": expected 'model_class legend_id'");
    }
    if (from < 0 || from >= class_count) {
      return makeError(source + ":" + std::to_string(number) + ": model class " + std::to_string(from) +
                       " outside 0.." + std::to_string(class_count - 1));
    }
    if (to < 0 || to > std::numeric_limits<LabelId>::max()) {
      return makeError(source + ":" + std::to_string(number) + ": legend id " + std::to_string(to) + " out of range");
    }
    map[static_cast<std::size_t>(from)] = static_cast<LabelId>(to);
  }
  return map;
}

Result<LabelMap> loadLabelMap(const std::filesystem::path& file, int class_count) {
  std::ifstream in(file);
  if (!in) return makeError("cannot read label map " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  return parseLabelMap(text.str(), class_count, file.string());
}

}  // namespace semfuse::segmentation
