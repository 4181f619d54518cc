#pragma once
// Nearest binary descriptors (ORB's 256 bits) by Hamming distance, brute force over rows. OpenCV's
// matcher counts bits through a byte table on builds without a popcount baseline (Debian's), about
// four times slower than the popcount instruction used here where the CPU has it.
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace semfuse::tracking {

struct NearestTwo {
  int best = -1;  // row of the train matrix, -1 when it is empty
  int best_distance = 257;
  int second = -1;
  int second_distance = 257;
};

// For every row of `query` (CV_8UC1, 32 bytes a row), the two nearest rows of `train`; the work is
// spread over the TBB workers.
std::vector<NearestTwo> nearestTwo(const cv::Mat& query, const cv::Mat& train);

}  // namespace semfuse::tracking
