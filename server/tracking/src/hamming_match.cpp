#include "semfuse/tracking/hamming_match.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "hamming_scan.hpp"

namespace semfuse::tracking {

#if defined(SEMFUSE_HAVE_POPCNT_SCAN)
void scanRangePopcnt(const cv::Mat& query, const cv::Mat& train, int begin, int end, NearestTwo* out);
#endif

std::vector<NearestTwo> nearestTwo(const cv::Mat& query, const cv::Mat& train) {
  std::vector<NearestTwo> out(static_cast<std::size_t>(query.rows));
  if (query.empty() || train.empty() || query.cols != 32 || train.cols != 32) return out;
#if defined(SEMFUSE_HAVE_POPCNT_SCAN)
  static const bool popcnt = __builtin_cpu_supports("popcnt");
#else
  constexpr bool popcnt = false;
#endif
  tbb::parallel_for(tbb::blocked_range<int>(0, query.rows, 16), [&](const tbb::blocked_range<int>& range) {
#if defined(SEMFUSE_HAVE_POPCNT_SCAN)
    if (popcnt) {
      scanRangePopcnt(query, train, range.begin(), range.end(), out.data());
      return;
    }
#endif
    scanRange(query, train, range.begin(), range.end(), out.data());
  });
  return out;
}

}  // namespace semfuse::tracking
