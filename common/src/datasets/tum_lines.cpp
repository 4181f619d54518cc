#include "tum_lines.hpp"

#include <fstream>

namespace semfuse::datasets {
namespace fs = std::filesystem;

Result<std::vector<std::pair<int, std::string>>> tumDataLines(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return makeError("TUM file missing or unreadable: " + file.string());
  std::vector<std::pair<int, std::string>> lines;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    lines.emplace_back(number, line);
  }
  return lines;
}

Error tumLineError(const fs::path& file, int line, const std::string& what) {
  return makeError(file.string() + ":" + std::to_string(line) + ": " + what);
}

}  // namespace semfuse::datasets
