#pragma once
// The measured part of the ingest bench, against a server that is already up: for each camera
// count, N cameras stream at the given rate for the run's duration (camera k replays the sequence
// from k/N of it, under its own camera_id, phases spread over one period); then 2 cameras stream
// while a client raycasts from where camera 0 is, and a last burst of raycasts runs with no
// camera. The map is reset before each run; the server is drained after it.
#include <sys/types.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include "camera_stream.hpp"
#include "followed_updates.hpp"
#include "ingest_options.hpp"
#include "ingest_report.hpp"
#include "pose_collector.hpp"
#include "preloaded_frames.hpp"
#include "process_stats.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/writer.hpp"

namespace semfuse::bench::ingest {

class IngestRuns {
 public:
  IngestRuns(const IngestOptions& options, const Preloaded& data, dds_domainid_t domain);

  // Runs every configuration and prints the table; `pid` is the server's process. Returns the
  // exit code.
  int run(pid_t pid);

 private:
  using Clock = std::chrono::steady_clock;

  Result<client::ServerStatus> stats();
  Result<RunResult> runOnce(pid_t pid, RssMonitor& rss, int cameras, double duration_s, bool with_raycast);
  Result<client::ServerStatus> drain(uint64_t expected_received);
  void raycastUntil(Clock::time_point end, const std::atomic<std::size_t>& camera0_index, RunResult& run);
  RunResult idleRaycasts();
  void measureUpdates(RunResult& run);

  const IngestOptions& options_;
  const Preloaded& data_;
  dds::Participant participant_;
  dds::Topic<FrameMsg> frame_topic_;
  client::MapClient map_;
  PoseCollector poses_;
  std::vector<std::unique_ptr<dds::Writer<FrameMsg>>> writers_;
  std::unique_ptr<FollowedUpdates> follower_;  // with --follow-map
};

}  // namespace semfuse::bench::ingest
