#pragma once
// What one run of the load bench measured, for the report and the --check verdict.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "bench_support.hpp"
#include "ingest/camera_stream.hpp"
#include "ingest/pose_collector.hpp"
#include "ingest/process_stats.hpp"
#include "query_loop.hpp"
#include "raycast_baseline.hpp"
#include "rss_timeline.hpp"
#include "semfuse/client/map_follower.hpp"
#include "semfuse/client/segmenter.hpp"
#include "semfuse/client/server_status.hpp"

namespace semfuse::bench::load {

struct CameraRun {
  std::string camera_id;
  bool posed = true;
  ingest::CameraResult sent;
};

struct LoadResult {
  double duration_s = 0;
  std::vector<CameraRun> cameras;
  std::vector<client::SegmenterStats> segmenters;
  client::ServerStatus before, after;
  std::vector<ingest::PoseRecord> poses;
  bool followed = false;
  Timings update_latency_ms;
  std::size_t map_updates = 0;
  client::MapFollowerStats follower;
  std::vector<QueryStats> queries;
  double server_cpu_percent = 0, bench_cpu_percent = 0;
  std::vector<ingest::ThreadCpuShare> server_threads;  // busiest first
  RssSummary rss;
  double load_start = 0, load_end = 0;  // 1-minute load average
  RaycastBaseline idle;
};

}  // namespace semfuse::bench::load
