#include "load_run.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <utility>

#include "bench_support.hpp"
#include "depth_band_segmenter.hpp"
#include "ingest/camera_stream.hpp"
#include "ingest/interrupt.hpp"
#include "ingest/process_stats.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topics.hpp"

namespace semfuse::bench::load {
namespace {

using Clock = std::chrono::steady_clock;

// Where each camera starts in the sequence: posed camera p from p/P of it; a tracked camera
// follows a posed one half a second behind (another robot on the same route), so that the
// keyframes of the map it joins can place it.
struct CameraPlan {
  std::string camera_id;
  bool posed = true;
  std::size_t first = 0;
};

std::vector<CameraPlan> planCameras(const LoadOptions& options, std::size_t frames) {
  std::vector<CameraPlan> plan;
  int posed = 0, tracked = 0;
  const auto posed_total = static_cast<std::size_t>(std::max(options.posed_cameras, 0));
  const auto tracked_total = static_cast<std::size_t>(std::max(options.tracked_cameras, 0));
  constexpr std::size_t kFollowLag = 15;  // frames: 0.5 s at 30 Hz
  while (static_cast<std::size_t>(posed) < posed_total || static_cast<std::size_t>(tracked) < tracked_total) {
    // Alternate posed and tracked, posed first, so that segmenters 0 and 1 get one of each.
    const bool take_posed = static_cast<std::size_t>(posed) < posed_total &&
                            (posed <= tracked || static_cast<std::size_t>(tracked) == tracked_total);
    if (take_posed) {
      plan.push_back({"load-posed-" + std::to_string(posed), true, frames * posed / posed_total});
      ++posed;
    } else {
      const std::size_t leader =
          posed_total ? frames * (tracked % posed_total) / posed_total : frames * tracked / tracked_total;
      plan.push_back({"load-tracked-" + std::to_string(tracked), false, (leader + kFollowLag) % frames});
      ++tracked;
    }
  }
  return plan;
}

// A grid of points 1.5 m in front of the camera, 1 m x 0.5 m: what a planner would ask about.
std::vector<Eigen::Vector3d> pointsInView(const Pose& camera_to_world) {
  std::vector<Eigen::Vector3d> points;
  for (int row = 0; row < 10; ++row)
    for (int col = 0; col < 20; ++col)
      points.push_back(camera_to_world * Eigen::Vector3d(-0.5 + col * 0.05, -0.25 + row * 0.05, 1.5));
  return points;
}

}  // namespace

LoadRun::LoadRun(const LoadOptions& options, const ingest::Preloaded& data, dds_domainid_t domain)
    : options_(options),
      data_(data),
      participant_(domain),
      frame_topic_(participant_, dds::topics::kFrames),
      map_(participant_),
      poses_(participant_) {
  if (options.follow_map) follower_ = std::make_unique<ingest::FollowedUpdates>(participant_);
}

// Discovery happens here, outside the measurement: a camera writer the server has not matched
// yet would lose its first frames, a segmenter its first labels.
Status LoadRun::connect() {
  const std::vector<CameraPlan> plan = planCameras(options_, data_.frames.size());
  for (std::size_t k = 0; k < plan.size(); ++k) {
    writers_.push_back(std::make_unique<dds::Writer<ingest::FrameMsg>>(frame_topic_, dds::qos::frames()));
    if (!writers_.back()->waitForReaders(1, DDS_SECS(30)))
      return makeError("the server's frames reader did not match within 30 s");
  }
  if (!map_.waitForStatus(std::chrono::seconds(30))) return makeError("no status from the server within 30 s");
  auto legend = map_.waitForLegend(std::chrono::seconds(30));
  if (!legend) return makeError("no label legend from the server within 30 s");
  const std::vector<LabelId> labels = foregroundLabels(*legend, 6);
  const int every = std::max(1, static_cast<int>(std::lround(options_.camera_hz / options_.segmenter_hz)));
  for (int s = 0; s < options_.segmenters && !plan.empty(); ++s) {
    client::SegmenterOptions segmenter;
    segmenter.segmenter_id = "load-segmenter-" + std::to_string(s);
    segmenter.camera_id = plan[static_cast<std::size_t>(s) % plan.size()].camera_id;
    segmenter.every = every;
    segmenters_.push_back(
        std::make_unique<client::Segmenter>(participant_, depthBandSegmenter(labels), std::move(segmenter)));
    segmenters_.back()->start();
    if (!segmenters_.back()->waitForCamera(std::chrono::seconds(30)))
      return makeError("a segmenter did not match the cameras within 30 s");
  }
  return {};
}

std::vector<std::unique_ptr<QueryLoop>> LoadRun::makeQueries(const std::atomic<std::size_t>& camera0_index) {
  const auto timeout = std::chrono::milliseconds(static_cast<long>(options_.query_timeout_s * 1000));
  auto pose = [this, &camera0_index] { return data_.poses[camera0_index.load()]; };
  std::vector<std::unique_ptr<QueryLoop>> loops;
  if (options_.raycast_hz > 0) {
    loops.push_back(std::make_unique<QueryLoop>(
        participant_, "raycast 640x480 d+n+l", options_.raycast_hz, [this, pose, timeout](client::MapClient& map) {
          constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
          return outcomeOf(map.raycast(pose(), data_.intrinsics, kLayers, timeout));
        }));
  }
  if (options_.query_hz > 0) {
    loops.push_back(std::make_unique<QueryLoop>(
        participant_, "labels_at 200 points", options_.query_hz,
        [pose, timeout](client::MapClient& map) { return outcomeOf(map.labelsAt(pointsInView(pose()), timeout)); }));
    const double max_age = options_.objects_max_age_s;
    const std::string objects_name =
        max_age > 0.0 ? "objects (all labels, max age " + formatNumber(max_age, 1) + " s)" : "objects (all labels)";
    loops.push_back(std::make_unique<QueryLoop>(participant_, objects_name, options_.query_hz,
                                                [timeout, max_age](client::MapClient& map) {
                                                  ObjectsRequest request;
                                                  request.min_voxels = 200;
                                                  request.max_age_s = max_age;
                                                  return outcomeOf(map.objects(request, timeout));
                                                }));
    loops.push_back(std::make_unique<QueryLoop>(
        participant_, "distance 200 points", options_.query_hz,
        [pose, timeout](client::MapClient& map) { return outcomeOf(map.distances(pointsInView(pose()), timeout)); }));
  }
  return loops;
}

Result<LoadResult> LoadRun::run(pid_t pid) {
  if (Status connected = connect(); !connected) return makeError(connected.error());
  const std::vector<CameraPlan> plan = planCameras(options_, data_.frames.size());
  std::atomic<std::size_t> camera0_index{plan.empty() ? 0 : plan.front().first};
  std::vector<std::unique_ptr<QueryLoop>> queries = makeQueries(camera0_index);
  for (auto& query : queries) static_cast<void>(query->warmUp());

  if (auto reset = map_.reset(std::chrono::seconds(30)); !reset) return makeError("reset: " + reset.error());
  std::this_thread::sleep_for(std::chrono::seconds(1));  // let discovery settle on the server's side too
  static_cast<void>(poses_.take());
  if (follower_) follower_->clear();
  LoadResult result;
  result.duration_s = options_.duration_s;
  auto before = map_.stats(std::chrono::seconds(10));
  if (!before) return makeError("stats: " + before.error());
  result.before = std::move(before).value();
  result.load_start = loadAverage();

  std::printf(
      "running %zu cameras (%d tracked) x %.0f Hz, %zu segmenters x %.0f Hz, %zu query clients, %s for %.0f s ...\n",
      plan.size(), options_.tracked_cameras, options_.camera_hz, segmenters_.size(), options_.segmenter_hz,
      queries.size(), follower_ ? "a map follower" : "no map follower", options_.duration_s);
  std::fflush(stdout);
  RssTimeline rss(pid, [this] {
    const auto status = map_.latestStatus();
    constexpr double kMiB = 1024.0 * 1024.0;
    return status ? MapMiB{static_cast<double>(status->map_bytes) / kMiB,
                           static_cast<double>(status->snapshot_bytes) / kMiB}
                  : MapMiB{};
  });
  const ingest::CpuSample cpu_start = ingest::sampleCpu(pid);
  const ingest::CpuSample bench_cpu_start = ingest::sampleCpu(::getpid());

  // Cameras start together with phases spread over one period, as independent sensors would be.
  const auto period =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / options_.camera_hz));
  const auto slots = static_cast<std::size_t>(options_.duration_s * options_.camera_hz);
  const auto start = Clock::now() + std::chrono::milliseconds(100);
  const auto end = start + period * static_cast<long>(slots);
  std::vector<ingest::CameraResult> sent(plan.size());
  std::vector<std::thread> cameras;
  for (std::size_t k = 0; k < plan.size(); ++k)
    cameras.emplace_back(ingest::runCamera, std::cref(data_), std::cref(*writers_[k]), plan[k].camera_id, plan[k].first,
                         start + period * static_cast<long>(k) / static_cast<long>(plan.size()), period, slots,
                         std::ref(sent[k]), k == 0 ? &camera0_index : nullptr, plan[k].posed);
  // Queries start once the map holds something to answer from.
  std::this_thread::sleep_until(start + std::chrono::milliseconds(500));
  for (auto& query : queries) query->start();
  for (auto next = start + std::chrono::seconds(10); Clock::now() < end && !ingest::interrupted();) {
    std::this_thread::sleep_until(std::min(end, Clock::now() + std::chrono::milliseconds(200)));
    if (Clock::now() >= next && Clock::now() < end) {
      showProgress(std::chrono::duration<double>(Clock::now() - start).count());
      next += std::chrono::seconds(10);
    }
  }
  for (auto& camera : cameras) camera.join();
  // A reliable writer keeps its last frames until the server acknowledges them; under load that
  // can take longer than the drain's quiet second, and a frame lost at the tail of a stream is
  // never revealed by a later sequence number. So the drain starts once every frame is delivered.
  for (std::size_t k = 0; k < writers_.size(); ++k)
    if (const Status acked = writers_[k]->waitForAcknowledgements(DDS_SECS(30)); !acked)
      std::printf("warning: %s: frames not acknowledged by the server within 30 s (%s)\n", plan[k].camera_id.c_str(),
                  acked.error().c_str());
  for (auto& query : queries) query->stop();
  result.rss = rss.summary();  // the load's window, not the drain's quiet seconds
  const ingest::CpuSample cpu_end = ingest::sampleCpu(pid);
  const ingest::CpuSample bench_cpu_end = ingest::sampleCpu(::getpid());
  result.load_end = loadAverage();
  result.server_cpu_percent = ingest::processPercent(cpu_start, cpu_end);
  result.bench_cpu_percent = ingest::processPercent(bench_cpu_start, bench_cpu_end);
  result.server_threads = ingest::threadShares(cpu_start, cpu_end);
  for (auto& query : queries) result.queries.push_back(query->stats());

  // Segmenters finish the frame in hand and publish it; then the server drains what it holds.
  for (auto& segmenter : segmenters_) {
    segmenter->stop();
    static_cast<void>(segmenter->waitForAcknowledgements(std::chrono::seconds(10)));
    result.segmenters.push_back(segmenter->stats());
  }
  auto after = drain();
  if (!after) return makeError(after.error());
  result.after = std::move(after).value();
  for (std::size_t k = 0; k < plan.size(); ++k) result.cameras.push_back({plan[k].camera_id, plan[k].posed, sent[k]});

  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // the last poses and map update in flight
  result.poses = poses_.take();
  if (follower_) {
    const std::vector<ingest::UpdateArrival> arrivals = follower_->arrivals();
    result.followed = true;
    result.map_updates = arrivals.size();
    result.update_latency_ms = ingest::updateLatencies(result.poses, arrivals);
    result.follower = follower_->followerStats();
  }

  if (!ingest::interrupted()) {
    std::printf("timing the raycast with nothing else running, through the server and in the library ...\n");
    std::fflush(stdout);
    std::vector<Pose> views;
    for (std::size_t v = 0; v < 4; ++v) views.push_back(data_.poses[v * data_.poses.size() / 4]);
    result.idle = measureIdleRaycasts(map_, pid, views, data_.intrinsics, 5);
  }
  return result;
}

// From the server's latest status: the camera threads' own counts are read only once they ended.
void LoadRun::showProgress(double elapsed_s) {
  const auto status = map_.latestStatus();
  uint64_t received = 0, integrated = 0, queue_drops = 0;
  if (status) {
    received = status->frames_received;
    integrated = status->frames_integrated;
    for (const auto& c : status->dropped)
      if (c.reason == "queue_full" || c.reason == "queue_stale") queue_drops += c.count;
  }
  std::printf("  %4.0f s: %llu frames received, %llu integrated, %llu queue drops, server RSS %.0f MiB, load %.2f\n",
              elapsed_s, static_cast<unsigned long long>(received), static_cast<unsigned long long>(integrated),
              static_cast<unsigned long long>(queue_drops),
              status ? static_cast<double>(status->rss_bytes) / (1024.0 * 1024.0) : 0.0, loadAverage());
  std::fflush(stdout);
}

// Until the server holds nothing more (no queued frame, no waiting segmentation, counters still
// for a second), or 30 s.
Result<client::ServerStatus> LoadRun::drain() {
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  client::ServerStatus last;
  for (int quiet_polls = 0;; std::this_thread::sleep_for(std::chrono::milliseconds(200))) {
    auto status = map_.stats(std::chrono::seconds(10));
    if (!status) return makeError("stats: " + status.error());
    const client::ServerStatus& now = status.value();
    const bool quiet = now.queued_frames == 0 && now.pending_segmentations == 0 &&
                       now.frames_received == last.frames_received && now.frames_integrated == last.frames_integrated &&
                       now.segmentations_received == last.segmentations_received;
    quiet_polls = quiet ? quiet_polls + 1 : 0;
    last = std::move(status).value();
    if (quiet_polls >= 5 || Clock::now() > deadline || ingest::interrupted()) break;
  }
  return last;
}

}  // namespace semfuse::bench::load
