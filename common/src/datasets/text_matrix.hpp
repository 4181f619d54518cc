#pragma once
// Reads a whitespace-separated matrix of numbers from a small text file (private helper).
#include <filesystem>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"

namespace semfuse::datasets::detail {

// All numbers of the file, which must hold exactly `expected_count` finite values.
Result<std::vector<double>> readNumbers(const std::filesystem::path& file, std::size_t expected_count,
                                        const std::string& what);

}  // namespace semfuse::datasets::detail
