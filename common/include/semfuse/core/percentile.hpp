#pragma once
// The p-th percentile of sorted samples by nearest rank: the smallest sample that at least p % of
// them do not exceed. One definition for what the server reports and what the benchmarks print.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace semfuse {

// `sorted` ascending and not empty; p in [0, 100].
template <class T>
T nearestRankPercentile(const std::vector<T>& sorted, double p) {
  const auto rank = static_cast<std::size_t>(std::ceil(p / 100.0 * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}

}  // namespace semfuse
