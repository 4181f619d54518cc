#pragma once
// The line format shared by TUM RGB-D's list files (rgb.txt, depth.txt) and trajectory files
// (groundtruth.txt, an estimate): '#' comments and blank lines skipped, errors naming file:line.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "semfuse/core/result.hpp"

namespace semfuse::datasets {

// The data lines of `file` with their line numbers.
Result<std::vector<std::pair<int, std::string>>> tumDataLines(const std::filesystem::path& file);

// "file:line: what".
Error tumLineError(const std::filesystem::path& file, int line, const std::string& what);

}  // namespace semfuse::datasets
