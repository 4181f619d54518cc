#include "load_report.hpp"

#include <algorithm>
#include <cstdio>
#include <thread>

#include "input_accounting.hpp"

namespace semfuse::bench::load {
namespace {

// Aligned columns, the first row a header.
void printRows(const std::vector<std::vector<std::string>>& rows) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    width.resize(std::max(width.size(), row.size()));
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  for (std::size_t r = 0; r < rows.size(); ++r) {
    std::string line;
    for (std::size_t c = 0; c < rows[r].size(); ++c)
      line += rows[r][c] + std::string(width[c] - rows[r][c].size() + 2, ' ');
    std::printf("  %s\n", line.c_str());
    if (r == 0) std::printf("  %s\n", std::string(line.size(), '-').c_str());
  }
}

std::string percentiles(const Timings& t, int decimals = 1) {
  if (t.count() == 0) return "-";
  return formatNumber(t.median(), decimals) + " / " + formatNumber(t.p95(), decimals);
}

std::string verdict(bool met) { return met ? "met" : "MISSED"; }

struct StageTimings {
  Timings posed_latency, tracked_latency, all_latency, track, integrate;
};

StageTimings stageTimings(const LoadResult& result) {
  StageTimings s;
  for (const auto& pose : result.poses) {
    bool posed = true;
    for (const auto& camera : result.cameras)
      if (camera.camera_id == pose.camera_id) posed = camera.posed;
    if (!pose.integrated) continue;
    (posed ? s.posed_latency : s.tracked_latency).add(pose.latency_ms);
    s.all_latency.add(pose.latency_ms);
    if (!posed) s.track.add(pose.track_ms);
    s.integrate.add(pose.integrate_ms);
  }
  return s;
}

const QueryStats* findQuery(const LoadResult& result, const std::string& prefix) {
  for (const auto& q : result.queries)
    if (q.name.rfind(prefix, 0) == 0) return &q;
  return nullptr;
}

}  // namespace

void printLoadReport(const LoadResult& result, const LoadOptions& options, const ingest::Preloaded& data) {
  const double mib = 1024.0 * 1024.0;
  std::printf(
      "\ninputs (server status counters over the run; head loss = sent before the first frame the server received, "
      "at most %lld; unaccounted = lost without a counted reason):\n",
      static_cast<long long>(kMaxHeadLoss));
  std::vector<std::vector<std::string>> inputs{{"input", "sent", "received", "integrated", "dropped by reason",
                                                "head loss", "rejected by reason", "unaccounted"}};
  for (const InputAccount& row : accountInputs(result))
    inputs.push_back({row.what, std::to_string(row.sent) + " (" + formatNumber(row.sent / result.duration_s, 1) + "/s)",
                      std::to_string(row.received), std::to_string(row.integrated), reasonsText(row.dropped),
                      std::to_string(row.head_loss), reasonsText(row.rejected), std::to_string(row.unaccounted())});
  printRows(inputs);
  std::size_t skipped = 0;
  for (const auto& camera : result.cameras) skipped += camera.sent.skipped_slots;
  std::size_t seg_skipped = 0;
  double seg_ms = 0;
  for (const auto& s : result.segmenters) {
    seg_skipped += s.skipped;
    seg_ms += s.meanSegmentMs() / static_cast<double>(result.segmenters.size());
  }
  std::printf(
      "  camera slots skipped (a write still blocked at the next slot): %zu; segmenter frames replaced by a "
      "newer one: %zu\n",
      skipped, seg_skipped);

  const StageTimings stages = stageTimings(result);
  std::printf(
      "\nstages, ms p50 / p95 (what the server reports: TrackedPose track_ms and integrate_ms, and its status):\n");
  std::vector<std::vector<std::string>> stage_rows{{"stage", "p50 / p95 ms", "n", "what"}};
  stage_rows.push_back({"integration, posed cameras", percentiles(stages.posed_latency),
                        std::to_string(stages.posed_latency.count()), "camera publish -> TrackedPose received"});
  stage_rows.push_back({"integration, tracked cameras", percentiles(stages.tracked_latency),
                        std::to_string(stages.tracked_latency.count()), "camera publish -> TrackedPose received"});
  // The server's own stage timings, from its status at the end: over each stage's last 1,000 runs.
  const auto server_stage = [&](const char* name, const std::string& label, const std::string& what) {
    for (const auto& t : result.after.stages)
      if (t.stage == name) {
        stage_rows.push_back({label, formatNumber(t.p50_ms, 1) + " / " + formatNumber(t.p95_ms, 1),
                              std::to_string(t.count), what + " (server status, last 1,000)"});
        return;
      }
    stage_rows.push_back({label, "-", "0", what});
  };
  server_stage("frame_decode", "decode", "ingest thread, frame from its wire message");
  server_stage("frame_queue", "queue wait", "decoded -> taken by the fusion thread");
  stage_rows.push_back(
      {"track", percentiles(stages.track), std::to_string(stages.track.count()), "tracked cameras, fusion thread"});
  stage_rows.push_back({"integrate", percentiles(stages.integrate), std::to_string(stages.integrate.count()),
                        "fusion thread, with the labels of a segmentation that came first"});
  server_stage("late_labels", "labels (late pass)", "a segmentation fused after its frame");
  server_stage("map_update", "map update round", "changed blocks meshed and published");
  server_stage("distance_field", "distance field update", "from the changed leaves");
  if (result.followed)
    stage_rows.push_back({"map update publishing", percentiles(result.update_latency_ms, 0),
                          std::to_string(result.update_latency_ms.count()),
                          "frame integrated -> follower's update (" + std::to_string(result.map_updates) +
                              " updates, " + std::to_string(result.follower.gaps) + " gaps, " +
                              std::to_string(result.follower.catch_ups) + " catch-ups)"});
  stage_rows.push_back({"segmenter function", formatNumber(seg_ms, 1) + " mean", "-", "client side, depth bands"});
  printRows(stage_rows);

  std::printf("\nqueries (each its own client; reply = request to decoded reply):\n");
  std::vector<std::vector<std::string>> query_rows{
      {"query", "rate", "asked", "answered", "refused", "unanswered", "p50 / p95 ms", "last error"}};
  for (const auto& q : result.queries)
    query_rows.push_back({q.name, formatNumber(q.rate_hz, 0) + " Hz", std::to_string(q.asked),
                          std::to_string(q.answered), std::to_string(q.refused),
                          std::to_string(q.unanswered + q.client_errors), percentiles(q.reply_ms),
                          q.last_error.substr(0, 60)});
  printRows(query_rows);

  std::printf(
      "\nCPU over the run (100 %% = 1 core of %u): server %.0f %%, this bench (cameras, segmenters, query "
      "clients, follower) %.0f %%; load average %.2f -> %.2f\n",
      std::thread::hardware_concurrency(), result.server_cpu_percent, result.bench_cpu_percent, result.load_start,
      result.load_end);
  std::vector<std::vector<std::string>> cpu_rows{{"server thread", "threads", "CPU %"}};
  for (const auto& t : result.server_threads)
    if (t.percent >= 0.5) cpu_rows.push_back({t.name, std::to_string(t.threads), formatNumber(t.percent, 1)});
  printRows(cpu_rows);

  const RssSummary& rss = result.rss;
  std::printf(
      "\nserver RSS over the run (%zu samples, 1 s apart): start %.0f, max %.0f, end %.0f MiB, slope %.1f "
      "MiB/min (second half %.1f MiB/min); the map %.0f -> %.0f MiB; RSS minus the map: slope %.1f MiB/min\n",
      rss.samples, rss.start_mib, rss.max_mib, rss.end_mib, rss.slope_mib_per_min, rss.late_slope_mib_per_min,
      rss.map_start_mib, rss.map_end_mib, rss.non_map_slope_mib_per_min);
  std::printf("  final map: %.0f MiB, %llu voxels\n", static_cast<double>(result.after.map_bytes) / mib,
              static_cast<unsigned long long>(result.after.allocated_voxels));

  const RaycastBaseline& idle = result.idle;
  const double ratio = idle.ratio.count() ? idle.ratio.median() : 0.0;
  std::printf(
      "\nraycast 640x480 d+n+l with nothing else running (the server %s after %.1f s), on the run's final map: "
      "server %s ms, library %s ms (p50 / p95); server / library per pose p50 %.2f, p95 %.2f%s%s\n",
      idle.quiet ? "quiet" : "STILL BUSY", idle.quiet_wait_s, percentiles(idle.server_ms).c_str(),
      percentiles(idle.library_ms).c_str(), ratio, idle.ratio.count() ? idle.ratio.p95() : 0.0,
      idle.error.empty() ? "" : "; ", idle.error.c_str());

  // The service's targets on 2 cores, 7-Scenes frames, 1 cm voxels.
  std::printf("\ntargets:\n");
  const int64_t queue_drops = droppedTotal(result, "queue_full") + droppedTotal(result, "queue_stale");
  int64_t unaccounted = 0;
  for (const InputAccount& row : accountInputs(result)) unaccounted += row.unaccounted();
  const QueryStats* raycast = findQuery(result, "raycast");
  std::vector<std::vector<std::string>> targets{{"target", "measured", ""}};
  targets.push_back({"nothing lost without a counted reason", std::to_string(unaccounted), verdict(unaccounted == 0)});
  targets.push_back({"0 queue drops", std::to_string(queue_drops), verdict(queue_drops == 0)});
  const Timings& lat = stages.all_latency;
  targets.push_back({"integration p50 <= 30 ms", lat.count() ? formatNumber(lat.median(), 1) : "-",
                     verdict(lat.count() && lat.median() <= 30)});
  targets.push_back({"integration p95 <= 60 ms", lat.count() ? formatNumber(lat.p95(), 1) : "-",
                     verdict(lat.count() && lat.p95() <= 60)});
  const bool raycast_measured = raycast && raycast->reply_ms.count();
  targets.push_back({"raycast p50 <= 40 ms under load",
                     raycast_measured ? formatNumber(raycast->reply_ms.median(), 1) : "-",
                     verdict(raycast_measured && raycast->reply_ms.median() <= 40)});
  targets.push_back({"idle raycast <= 1.1 x library", ratio > 0 ? formatNumber(ratio, 2) + " x" : "-",
                     verdict(ratio > 0 && ratio <= 1.1)});
  targets.push_back({"RSS flat (second half of the run)", formatNumber(rss.late_slope_mib_per_min, 1) + " MiB/min",
                     "the map grows " + formatNumber(rss.map_end_mib - rss.map_start_mib, 0) + " MiB in all"});
  printRows(targets);

  std::printf(
      "\nconditions: %zu 7-Scenes frames preloaded, depth %s (%.0f kB), colour jpeg (%.0f kB); %.0f s; cameras %.0f "
      "Hz; segmenters every %.0f-th frame; server %s\n",
      data.frames.size(), ingest::depthWireEncoding(options.depth).c_str(), data.depth_kb, data.color_kb,
      result.duration_s, options.camera_hz, std::max(1.0, options.camera_hz / options.segmenter_hz),
      result.after.version.c_str());
}

std::vector<std::string> checkFailures(const LoadResult& result) {
  std::vector<std::string> failures;
  for (const InputAccount& row : accountInputs(result)) {
    if (row.unaccounted() != 0)
      failures.push_back(row.what + ": " + std::to_string(row.unaccounted()) + " lost without a counted reason");
    if (row.head_loss > kMaxHeadLoss)
      failures.push_back(row.what + ": " + std::to_string(row.head_loss) +
                         " frames lost before the first received, more than the frames reader holds");
    if (row.sent == 0) failures.push_back(row.what + ": nothing sent");
  }
  for (const auto& q : result.queries) {
    if (q.asked == 0) failures.push_back(q.name + ": never asked");
    if (q.unanswered + q.client_errors > 0)
      failures.push_back(q.name + ": " + std::to_string(q.unanswered + q.client_errors) + " of " +
                         std::to_string(q.asked) + " without a reply (" + q.last_error + ")");
  }
  return failures;
}

}  // namespace semfuse::bench::load
