#pragma once
// The server's resident memory over a run, sampled every second from /proc beside the map's own
// size and that of its copies for queries from the status, so that growth of the map (which is
// expected while cameras explore) can be told apart from growth of everything else (which should
// be flat).
#include <sys/types.h>

#include <atomic>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace semfuse::bench::load {

struct RssSample {
  double t_s = 0;
  double rss_mib = 0;
  double map_mib = 0;
  double copies_mib = 0;  // the map's copies the server keeps for queries (ServerStatus::snapshot_bytes)
  double nonMapMiB() const { return rss_mib - map_mib - copies_mib; }
};

// The map's size and its copies', as the server reports them now (0 when unknown).
struct MapMiB {
  double map = 0, copies = 0;
};

struct RssSummary {
  double start_mib = 0, max_mib = 0, end_mib = 0;
  double slope_mib_per_min = 0;          // least squares over the samples
  double non_map_slope_mib_per_min = 0;  // of RSS minus the map's and its copies' bytes
  // Over the second half of the run: buffers that fill once (frame history, queues, snapshots)
  // make the start steep; a leak keeps the second half rising.
  double late_slope_mib_per_min = 0;
  double late_non_map_slope_mib_per_min = 0;  // RSS minus the map and its copies, second half
  double map_start_mib = 0, map_end_mib = 0;
  double copies_start_mib = 0, copies_end_mib = 0;
  std::size_t samples = 0;
};

class RssTimeline {
 public:
  RssTimeline(pid_t pid, std::function<MapMiB()> map_mib);
  ~RssTimeline();
  RssTimeline(const RssTimeline&) = delete;
  RssTimeline& operator=(const RssTimeline&) = delete;

  std::vector<RssSample> samples();
  RssSummary summary();

 private:
  void loop();

  pid_t pid_;
  std::function<MapMiB()> map_mib_;
  std::mutex mutex_;
  std::vector<RssSample> samples_;
  std::atomic<bool> running_{true};
  std::thread thread_;  // last: starts once the members above exist
};

}  // namespace semfuse::bench::load
