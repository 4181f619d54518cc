#pragma once
// Where every frame and segmentation of a load run ended, from the server's status counters
// (deltas over the run) beside what the bench sent: posed and then integrated or skipped,
// dropped or rejected under a reason, still held, or unaccounted (lost without a counted reason:
// the figure that must be 0).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "load_result.hpp"
#include "semfuse/dds/qos.hpp"

namespace semfuse::bench::load {

// The server's frames reader keeps its last samples of all cameras together
// (dds::qos::frameIngest): a camera can lose at most that many before the server takes its first.
inline constexpr int64_t kMaxHeadLoss = dds::qos::kFrameIngestDepth;

struct InputAccount {
  std::string what;    // a camera id, or "segmentations"
  bool frames = true;  // a camera's frames (posed, then integrated or skipped); else segmentations
  int64_t sent = 0, received = 0, posed = 0, integrated = 0, skipped = 0, held = 0;
  std::map<std::string, int64_t> dropped, rejected;  // by reason, nonzero only
  // Frames sent before the first one the server received: overwritten in its DDS reader while
  // the ingest was busy. No sequence gap can reveal them to the server (it has no earlier frame of
  // that camera), so the bench counts them from what it sent and the server's last sequence number.
  int64_t head_loss = 0;
  int64_t unaccounted() const;
};

// One row per camera, then the segmentations of all segmenters.
std::vector<InputAccount> accountInputs(const LoadResult& result);

// "queue_full 12, tracking_lost 3" or "0".
std::string reasonsText(const std::map<std::string, int64_t>& counts);

// Sum over cameras of one drop reason's delta over the run.
int64_t droppedTotal(const LoadResult& result, const std::string& reason);

}  // namespace semfuse::bench::load
