// Compiled with -mpopcnt (see CMakeLists.txt); called only where the CPU has the instruction.
#include "hamming_scan.hpp"

namespace semfuse::tracking {

void scanRangePopcnt(const cv::Mat& query, const cv::Mat& train, int begin, int end, NearestTwo* out) {
  scanRange(query, train, begin, end, out);
}

}  // namespace semfuse::tracking
