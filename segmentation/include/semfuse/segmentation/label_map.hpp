#pragma once
// Mapping from a model's class indices to the map's legend ids, read from a text file:
//
//   # model class   legend id
//   9               5          # VOC chair -> synthetic chair
//   11              4
//
// Classes not listed map to 0 (unlabeled: they change nothing in the map). Without a file the
// mapping is the identity, right for a model trained on the legend's own classes (ade20k, voc).
#include <filesystem>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse::segmentation {

// lookup[class] = legend id, for classes 0..class_count-1.
using LabelMap = std::vector<LabelId>;

LabelMap identityLabelMap(int class_count);
Result<LabelMap> loadLabelMap(const std::filesystem::path& file, int class_count);
Result<LabelMap> parseLabelMap(const std::string& text, int class_count, const std::string& source);

}  // namespace semfuse::segmentation
