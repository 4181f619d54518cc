#pragma once
// Where every frame and segmentation of a load run ended, from the server's status counters
// (deltas over the run) beside what the bench sent: integrated, dropped or rejected under a
// reason, still held, or unaccounted (lost without a counted reason: the figure that must be 0).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "load_result.hpp"

namespace semfuse::bench::load {

struct InputAccount {
  std::string what;  // a camera id, or "segmentations"
  int64_t sent = 0, received = 0, integrated = 0, held = 0;
  std::map<std::string, int64_t> dropped, rejected;  // by reason, nonzero only
  int64_t unaccounted() const;
};

// One row per camera, then the segmentations of all segmenters.
std::vector<InputAccount> accountInputs(const LoadResult& result);

// "queue_full 12, tracking_lost 3" or "0".
std::string reasonsText(const std::map<std::string, int64_t>& counts);

// Sum over cameras of one drop reason's delta over the run.
int64_t droppedTotal(const LoadResult& result, const std::string& reason);

}  // namespace semfuse::bench::load
