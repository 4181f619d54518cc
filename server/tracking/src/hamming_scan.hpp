#pragma once
// The brute-force scan behind nearestTwo(), compiled twice: with the popcount instruction
// (hamming_match_popcnt.cpp) and without (hamming_match.cpp). Internal linkage keeps the two
// copies apart.
#include <cstdint>
#include <cstring>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/tracking/hamming_match.hpp"

namespace semfuse::tracking {
namespace {

inline void scanRange(const cv::Mat& query, const cv::Mat& train, int begin, int end, NearestTwo* out) {
  for (int q = begin; q < end; ++q) {
    uint64_t a[4];
    std::memcpy(a, query.ptr(q), sizeof(a));
    NearestTwo nearest;
    for (int t = 0; t < train.rows; ++t) {
      uint64_t b[4];
      std::memcpy(b, train.ptr(t), sizeof(b));
      const int distance = __builtin_popcountll(a[0] ^ b[0]) + __builtin_popcountll(a[1] ^ b[1]) +
                           __builtin_popcountll(a[2] ^ b[2]) + __builtin_popcountll(a[3] ^ b[3]);
      if (distance < nearest.best_distance) {
        nearest.second = nearest.best;
        nearest.second_distance = nearest.best_distance;
        nearest.best = t;
        nearest.best_distance = distance;
      } else if (distance < nearest.second_distance) {
        nearest.second = t;
        nearest.second_distance = distance;
      }
    }
    out[q] = nearest;
  }
}

}  // namespace
}  // namespace semfuse::tracking
