#include "text_matrix.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace semfuse::datasets::detail {

Result<std::vector<double>> readNumbers(const std::filesystem::path& file, std::size_t expected_count,
                                        const std::string& what) {
  std::ifstream in(file);
  if (!in) return makeError(what + " missing or unreadable: " + file.string());
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    std::istringstream parse(token);
    double value = 0.0;
    if (!(parse >> value) || !parse.eof()) {
      return makeError(what + " " + file.string() + ": '" + token + "' is not a number");
    }
    if (!std::isfinite(value)) return makeError(what + " " + file.string() + ": non-finite value " + token);
    values.push_back(value);
  }
  if (values.size() != expected_count) {
    return makeError(what + " " + file.string() + ": " + std::to_string(values.size()) + " numbers, expected " +
                     std::to_string(expected_count));
  }
  return values;
}

}  // namespace semfuse::datasets::detail
