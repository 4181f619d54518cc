#pragma once
// The results of the ingest bench's runs and the table that compares them with the targets.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "ingest_options.hpp"
#include "pose_collector.hpp"
#include "preloaded_frames.hpp"
#include "process_stats.hpp"
#include "semfuse/client/server_status.hpp"

namespace semfuse::bench::ingest {

// One run: N cameras for a duration, optionally with raycast queries.
struct RunResult {
  std::string title;
  int cameras = 0;
  double duration_s = 0;
  std::size_t sent = 0, write_failures = 0, skipped_slots = 0;
  Timings write_ms;
  client::ServerStatus before, after;
  std::vector<PoseRecord> poses;
  double cpu_percent = 0, rss_peak_mib = 0;
  std::vector<ThreadCpuShare> server_threads;  // by name, busiest first
  double load_start = 0, load_end = 0;
  Timings raycast_ms;
  std::size_t raycast_failures = 0;
  std::string raycast_error;
  // With --follow-map: frame integrated (its pose received) -> the first map update received
  // that includes it, and the map updates received.
  Timings update_latency_ms;
  std::size_t map_updates = 0;
};

// The table of all runs (one column each, the target last), the busiest server threads, the
// raycast time with no camera streaming when measured (idle_raycast may be null) and the
// conditions.
void printResults(const std::vector<RunResult>& runs, const IngestOptions& options, const Preloaded& data,
                  const RunResult* idle_raycast);

}  // namespace semfuse::bench::ingest
