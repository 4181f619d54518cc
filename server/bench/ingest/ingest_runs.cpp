#include "ingest_runs.hpp"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <thread>
#include <utility>

#include "bench_support.hpp"
#include "interrupt.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topics.hpp"

namespace semfuse::bench::ingest {
IngestRuns::IngestRuns(const IngestOptions& options, const Preloaded& data, dds_domainid_t domain)
    : options_(options),
      data_(data),
      participant_(domain),
      frame_topic_(participant_, dds::topics::kFrames),
      map_(participant_),
      poses_(participant_) {
  if (options.follow_map) follower_ = std::make_unique<FollowedUpdates>(participant_);
}

int IngestRuns::run(pid_t pid) {
  // One writer per camera, created once: a writer the server's reader has not discovered yet
  // would lose its first frames, so discovery happens here, outside any measurement.
  const int max_cameras = std::max(2, *std::max_element(options_.cameras.begin(), options_.cameras.end()));
  for (int k = 0; k < max_cameras; ++k) {
    writers_.push_back(std::make_unique<dds::Writer<FrameMsg>>(frame_topic_, dds::qos::frames()));
    if (!writers_.back()->waitForReaders(1, DDS_SECS(30))) {
      std::fprintf(stderr, "the server's frames reader did not match within 30 s\n");
      return 1;
    }
  }
  if (!map_.waitForStatus(std::chrono::seconds(30))) {
    std::fprintf(stderr, "no status from the server within 30 s\n");
    return 1;
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));  // let discovery settle on the server's side too

  RssMonitor rss(pid);
  std::vector<RunResult> runs;
  for (int cameras : options_.cameras) {
    if (interrupted()) break;
    auto result = runOnce(pid, rss, cameras, options_.duration_s, false);
    if (!result) {
      std::fprintf(stderr, "%s\n", result.error().c_str());
      return 1;
    }
    runs.push_back(std::move(result).value());
  }
  std::optional<RunResult> idle;
  if (options_.raycast_duration_s > 0 && !interrupted()) {
    auto result = runOnce(pid, rss, 2, options_.raycast_duration_s, true);
    if (!result) {
      std::fprintf(stderr, "%s\n", result.error().c_str());
      return 1;
    }
    runs.push_back(std::move(result).value());
    idle = idleRaycasts();  // same map, no camera: what the streaming costs the query
  }
  if (interrupted()) std::printf("interrupted: partial results\n");
  printResults(runs, options_, data_, idle ? &*idle : nullptr);
  return 0;
}

Result<client::ServerStatus> IngestRuns::stats() {
  auto status = map_.stats(std::chrono::seconds(10));
  if (!status) return makeError("stats: " + status.error());
  return std::move(status).value();
}

Result<RunResult> IngestRuns::runOnce(pid_t pid, RssMonitor& rss, int cameras, double duration_s, bool with_raycast) {
  RunResult run;
  run.cameras = cameras;
  run.duration_s = duration_s;
  run.title = std::to_string(cameras) + (cameras == 1 ? " camera" : " cameras") + (with_raycast ? " + raycast" : "");
  std::printf("running %s for %.0f s ...\n", run.title.c_str(), duration_s);
  std::fflush(stdout);

  if (auto reset = map_.reset(std::chrono::seconds(30)); !reset) return makeError("reset: " + reset.error());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  poses_.take();  // nothing from before this run
  if (follower_) follower_->clear();
  auto before = stats();
  if (!before) return makeError(before.error());
  run.before = std::move(before).value();
  rss.resetPeak();
  run.load_start = loadAverage();

  // Cameras start together but with phases spread over one period, as independent sensors
  // would be; camera k replays the sequence from k/N of it.
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options_.rate_hz));
  const auto slots = static_cast<std::size_t>(duration_s * options_.rate_hz);
  const auto start = Clock::now() + std::chrono::milliseconds(100);
  std::vector<CameraResult> results(static_cast<std::size_t>(cameras));
  std::atomic<std::size_t> camera0_index{0};
  const std::string prefix = "c" + std::to_string(cameras) + (with_raycast ? "r" : "") + "-cam";
  const CpuSample cpu_start = sampleCpu(pid);
  std::vector<std::thread> threads;
  for (int k = 0; k < cameras; ++k) {
    const std::size_t first = data_.frames.size() * static_cast<std::size_t>(k) / static_cast<std::size_t>(cameras);
    threads.emplace_back(runCamera, std::cref(data_), std::cref(*writers_[static_cast<std::size_t>(k)]),
                         prefix + std::to_string(k), first, start + period * k / cameras, period, slots,
                         std::ref(results[static_cast<std::size_t>(k)]), k == 0 ? &camera0_index : nullptr, true);
  }
  if (with_raycast)
    raycastUntil(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(duration_s)),
                 camera0_index, run);
  for (auto& t : threads) t.join();
  const CpuSample cpu_end = sampleCpu(pid);
  run.load_end = loadAverage();

  // CPU over the publishing window (the drain below adds at most a few queued frames).
  run.cpu_percent = processPercent(cpu_start, cpu_end);
  run.server_threads = threadShares(cpu_start, cpu_end);

  for (const auto& r : results) {
    run.sent += r.sent;
    run.write_failures += r.write_failures;
    run.skipped_slots += r.skipped_slots;
    for (double ms : r.write_ms) run.write_ms.add(ms);
  }

  // Drain: wait until the server has taken everything it received (status stable, queue empty).
  auto after = drain(run.before.frames_received + run.sent);
  if (!after) return makeError(after.error());
  run.after = std::move(after).value();
  run.rss_peak_mib = rss.peak();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last poses in flight
  for (auto& p : poses_.take())
    if (p.camera_id.rfind(prefix, 0) == 0) run.poses.push_back(std::move(p));
  if (follower_) measureUpdates(run);
  return run;
}

void IngestRuns::measureUpdates(RunResult& run) {
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // the last round after the last frame
  const std::vector<UpdateArrival> arrivals = follower_->arrivals();
  run.map_updates = arrivals.size();
  run.update_latency_ms = updateLatencies(run.poses, arrivals);  // the map was reset before the run
}

Result<client::ServerStatus> IngestRuns::drain(uint64_t expected_received) {
  // Frames lost on the way never arrive, so "quiet for 1 s" also ends the wait.
  const auto deadline = Clock::now() + std::chrono::seconds(15);
  client::ServerStatus last;
  for (int quiet_polls = 0;; std::this_thread::sleep_for(std::chrono::milliseconds(200))) {
    auto status = stats();
    if (!status) return makeError(status.error());
    const bool quiet = status.value().queued_frames == 0 && status.value().frames_received == last.frames_received &&
                       status.value().frames_integrated == last.frames_integrated;
    quiet_polls = quiet ? quiet_polls + 1 : 0;
    last = std::move(status).value();
    if (quiet && (last.frames_received >= expected_received || quiet_polls >= 5)) break;
    if (Clock::now() > deadline || interrupted()) break;
  }
  return last;
}

// Raycasts from where camera 0 was a moment ago (the live view a viewer would show), one every
// raycast_period_ms, or back to back when a reply takes longer.
void IngestRuns::raycastUntil(Clock::time_point end, const std::atomic<std::size_t>& camera0_index, RunResult& run) {
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let the map hold something
  const auto period = std::chrono::milliseconds(options_.raycast_period_ms);
  constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
  for (auto next = Clock::now(); Clock::now() < end && !interrupted(); next += period) {
    std::this_thread::sleep_until(next);
    const Pose pose = data_.poses[camera0_index.load()];
    Stopwatch watch;
    auto view = map_.raycast(pose, data_.intrinsics, kLayers, std::chrono::seconds(5));
    if (view) {
      run.raycast_ms.add(watch.elapsedMs());
    } else {
      ++run.raycast_failures;
      run.raycast_error = view.error();
    }
    next = std::max(next, Clock::now() - period);
  }
}

RunResult IngestRuns::idleRaycasts() {
  RunResult run;
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
  for (int i = 0; i < 20 && !interrupted(); ++i) {
    Stopwatch watch;
    auto view = map_.raycast(data_.poses[0], data_.intrinsics, kLayers, std::chrono::seconds(5));
    if (view) run.raycast_ms.add(watch.elapsedMs());
  }
  return run;
}

}  // namespace semfuse::bench::ingest
