#pragma once
// How long each stage of the server's work takes, for the status: operators and the load bench
// see where a frame's time goes (decode, wait in the queue, track, integrate) and what the
// threads beside the fusion cost (late label passes, live mesh rounds, distance field updates),
// as percentiles over the most recent runs. Safe to record from any thread: a stage records at
// most a few hundred times a second, so one short lock per sample is cheap.
#include <array>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <vector>

#include "semfuse/core/server_status.hpp"

namespace semfuse::server {

enum class Stage : int {
  kFrameDecode,       // a frame from its wire message (ingest thread); from ROS 2 topics, each image
                      // (depth, colour) is a run
  kFrameQueue,        // a frame's wait in its camera's queue, from decoded to taken by a tracking thread
  kTrack,             // the frame's pose: tracking, or checking a given pose
  kIntegrationQueue,  // a tracked frame's wait for the fusion thread (integrated, skipped or kept)
  kIntegrate,         // depth (and labels that came first) into the map, with the wait for its lock
  kLateLabels,        // a segmentation that came after its frame, fused on its own
  kMapUpdate,         // one round of the live mesh (changed blocks meshed and published)
  kDistanceField,     // one update of the distance field from the changed leaves
  kCount
};

const char* stageName(Stage stage);

class StageTimings {
 public:
  static constexpr std::size_t kWindow = 1000;  // the runs a stage's percentiles cover

  void record(Stage stage, double ms);
  // The run from `start` to now.
  void recordSince(Stage stage, std::chrono::steady_clock::time_point start);
  // The stages that ran at least once, in the enum's order.
  std::vector<StageTiming> summary() const;

 private:
  struct Samples {
    uint64_t count = 0;
    std::vector<float> recent;  // a ring of the last kWindow, next at count % kWindow
  };
  mutable std::mutex mutex_;
  std::array<Samples, static_cast<std::size_t>(Stage::kCount)> stages_;
};

}  // namespace semfuse::server
