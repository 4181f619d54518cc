#include "load_report.hpp"

#include <algorithm>
#include <cstdio>
#include <thread>

#include "input_accounting.hpp"
#include "load_figures.hpp"

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

std::string percent(int64_t part, int64_t whole) {
  return whole > 0 ? formatNumber(100.0 * static_cast<double>(part) / static_cast<double>(whole), 1) + " %" : "-";
}

// Tracking time of the cameras the server tracks, from their TrackedPose.
Timings trackTimes(const LoadResult& result) {
  Timings track;
  for (const auto& pose : result.poses)
    for (const auto& camera : result.cameras)
      if (camera.camera_id == pose.camera_id && !camera.posed && pose.posed) track.add(pose.track_ms);
  return track;
}

void printCameras(const LoadFigures& figures) {
  std::printf(
      "\ncameras (posed: given or tracked a pose, %% of sent; skipped: posed, passed over by integration for a newer "
      "frame, %% of posed; share: integrated / the cameras' mean):\n");
  std::vector<std::vector<std::string>> rows{{"camera", "sent", "posed", "lost", "publish -> pose p50 / p95 ms",
                                              "integrated", "integrated/s", "skipped", "share"}};
  for (const CameraFigures& c : figures.cameras)
    rows.push_back({c.camera_id + (c.posed_camera ? " (posed)" : " (tracked)"), std::to_string(c.sent),
                    std::to_string(c.posed) + " (" + percent(c.posed, c.sent) + ")", std::to_string(c.lost),
                    percentiles(c.pose_latency_ms), std::to_string(c.integrated),
                    formatNumber(static_cast<double>(c.integrated) / figures.duration_s, 1),
                    std::to_string(c.skipped) + " (" + percent(c.skipped, c.posed) + ")",
                    formatNumber(c.integrated_share, 2)});
  printRows(rows);
  std::printf(
      "  all: %.1f frames/s posed, %.1f integrated/s; the server used %.2f cores: %.1f frames integrated per "
      "core-second\n",
      figures.posed_per_s, figures.integrated_per_s, figures.server_cores, figures.integrated_per_core_s);
}

const QueryStats* findQuery(const LoadResult& result, const std::string& prefix) {
  for (const auto& q : result.queries)
    if (q.name.rfind(prefix, 0) == 0) return &q;
  return nullptr;
}

// The scenario's targets on 2 cores, 7-Scenes frames, 1 cm voxels, the default label rule.
void printTargets(const LoadResult& result, const LoadOptions& options, const LoadFigures& figures) {
  const bool robot = options.scenario == Scenario::kRobot;
  std::printf("\ntargets (%s scenario):\n", robot ? "robot" : "full");
  int64_t unaccounted = 0;
  for (const InputAccount& row : accountInputs(result)) unaccounted += row.unaccounted();
  std::size_t unanswered = 0;
  for (const auto& q : result.queries) unanswered += q.unanswered + q.client_errors;
  std::vector<std::vector<std::string>> targets{{"target", "measured", ""}};
  auto add = [&](const std::string& what, const std::string& measured, bool met) {
    targets.push_back({what, measured, verdict(met)});
  };
  auto share = [](int64_t part, int64_t whole) {
    return whole > 0 ? static_cast<double>(part) / static_cast<double>(whole) : 0.0;
  };
  const Timings& latency = robot ? figures.pose_latency_ms : figures.tracked_pose_latency_ms;
  const bool timed = latency.count() > 0;
  add("nothing lost without a counted reason", std::to_string(unaccounted), unaccounted == 0);
  add("every query answered", std::to_string(unanswered) + " unanswered", unanswered == 0);
  const double posed_share = share(figures.tracked_posed, figures.tracked_sent);
  const double lost_share = share(figures.tracked_lost, figures.tracked_sent);
  if (robot) {
    add("frames posed >= 99.5 %", percent(figures.tracked_posed, figures.tracked_sent), posed_share >= 0.995);
    add("tracking lost <= 1 %", percent(figures.tracked_lost, figures.tracked_sent), lost_share <= 0.01);
    add("publish -> pose p50 <= 25 ms", timed ? formatNumber(latency.median(), 1) : "-",
        timed && latency.median() <= 25);
    add("publish -> pose p95 <= 50 ms", timed ? formatNumber(latency.p95(), 1) : "-", timed && latency.p95() <= 50);
    add(">= 25 frames/s integrated", formatNumber(figures.integrated_per_s, 1), figures.integrated_per_s >= 25);
    add(">= 95 % of segmentations fused", percent(figures.segmentations_fused, figures.segmentations_sent),
        share(figures.segmentations_fused, figures.segmentations_sent) >= 0.95);
    const QueryStats* raycast = findQuery(result, "raycast");
    const bool raycast_timed = raycast && raycast->reply_ms.count();
    add("raycast p50 <= 60 ms", raycast_timed ? formatNumber(raycast->reply_ms.median(), 1) : "-",
        raycast_timed && raycast->reply_ms.median() <= 60);
    const QueryStats* objects = findQuery(result, "objects");
    const bool objects_timed = objects && objects->reply_ms.count();
    add("objects p50 <= 150 ms", objects_timed ? formatNumber(objects->reply_ms.median(), 1) : "-",
        objects_timed && objects->reply_ms.median() <= 150);
    add("RSS minus the map and its copies flat (second half) <= 5 MiB/min",
        formatNumber(result.rss.late_non_map_slope_mib_per_min, 1) + " MiB/min (a 300 s run tells)",
        result.rss.late_non_map_slope_mib_per_min <= 5);
  } else {
    add("tracked cameras' frames posed >= 99 %", percent(figures.tracked_posed, figures.tracked_sent),
        posed_share >= 0.99);
    add("tracked cameras' publish -> pose p95 <= 80 ms", timed ? formatNumber(latency.p95(), 1) : "-",
        timed && latency.p95() <= 80);
    add(">= 30 frames/s integrated in all", formatNumber(figures.integrated_per_s, 1), figures.integrated_per_s >= 30);
    add("each camera's integrations within 25 % of the mean",
        "worst " + formatNumber(100.0 * figures.worst_share_deviation, 0) + " % off",
        figures.worst_share_deviation <= 0.25);
  }
  printRows(targets);
}

}  // namespace

void printCoreComparison(const LoadResult& one_core, const LoadResult& every_core) {
  const LoadFigures a = loadFigures(one_core), b = loadFigures(every_core);
  auto ratio = [](double x, double y) { return y > 0 ? formatNumber(x / y, 2) + " x" : std::string("-"); };
  std::printf("\nthe server on every core against CPU 0 alone (same load, same frames):\n");
  std::vector<std::vector<std::string>> rows{{"", "CPU 0", "every core", "ratio"}};
  rows.push_back({"frames posed/s", formatNumber(a.posed_per_s, 1), formatNumber(b.posed_per_s, 1),
                  ratio(b.posed_per_s, a.posed_per_s)});
  rows.push_back({"frames integrated/s", formatNumber(a.integrated_per_s, 1), formatNumber(b.integrated_per_s, 1),
                  ratio(b.integrated_per_s, a.integrated_per_s)});
  rows.push_back({"posed + integrated /s", formatNumber(a.posed_per_s + a.integrated_per_s, 1),
                  formatNumber(b.posed_per_s + b.integrated_per_s, 1),
                  ratio(b.posed_per_s + b.integrated_per_s, a.posed_per_s + a.integrated_per_s)});
  rows.push_back({"publish -> pose p50 / p95 ms", percentiles(a.pose_latency_ms), percentiles(b.pose_latency_ms), ""});
  rows.push_back({"server CPU, cores", formatNumber(a.server_cores, 2), formatNumber(b.server_cores, 2),
                  ratio(b.server_cores, a.server_cores)});
  printRows(rows);
}

void printLoadReport(const LoadResult& result, const LoadOptions& options, const ingest::Preloaded& data) {
  const double mib = 1024.0 * 1024.0;
  std::printf(
      "\ninputs (server status counters over the run; head loss = sent before the first frame the server received, "
      "at most %lld; unaccounted = lost without a counted reason):\n",
      static_cast<long long>(kMaxHeadLoss));
  std::vector<std::vector<std::string>> inputs{{"input", "sent", "received", "posed", "integrated", "skipped",
                                                "dropped by reason", "head loss", "rejected by reason", "unaccounted"}};
  for (const InputAccount& row : accountInputs(result))
    inputs.push_back({row.what, std::to_string(row.sent) + " (" + formatNumber(row.sent / result.duration_s, 1) + "/s)",
                      std::to_string(row.received), row.frames ? std::to_string(row.posed) : "-",
                      std::to_string(row.integrated), row.frames ? std::to_string(row.skipped) : "-",
                      reasonsText(row.dropped), std::to_string(row.head_loss), reasonsText(row.rejected),
                      std::to_string(row.unaccounted())});
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

  const LoadFigures figures = loadFigures(result);
  printCameras(figures);

  const Timings track = trackTimes(result);
  std::printf("\nstages, ms p50 / p95 (what the server reports: TrackedPose track_ms, and its status):\n");
  std::vector<std::vector<std::string>> stage_rows{{"stage", "p50 / p95 ms", "n", "what"}};
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
  server_stage("frame_queue", "queue wait", "decoded -> taken by a tracking thread");
  stage_rows.push_back(
      {"track", percentiles(track), std::to_string(track.count()), "tracked cameras, a tracking thread"});
  server_stage("integration_queue", "integration wait", "posed -> taken by the fusion thread");
  server_stage("integrate", "integrate", "fusion thread, with the labels of a segmentation that came first");
  server_stage("late_labels", "labels (late pass)", "a segmentation fused after its frame");
  server_stage("map_update", "map update round", "changed blocks meshed and published");
  server_stage("distance_field", "distance field update", "from the changed leaves");
  if (result.followed)
    stage_rows.push_back({"map update publishing", percentiles(result.update_latency_ms, 0),
                          std::to_string(result.update_latency_ms.count()),
                          "pose -> follower's next update with more frames (" + std::to_string(result.map_updates) +
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
      "MiB/min (second half %.1f MiB/min); the map %.0f -> %.0f MiB, its copies for queries %.0f -> %.0f MiB; RSS "
      "minus the map and its copies: slope %.1f MiB/min\n",
      rss.samples, rss.start_mib, rss.max_mib, rss.end_mib, rss.slope_mib_per_min, rss.late_slope_mib_per_min,
      rss.map_start_mib, rss.map_end_mib, rss.copies_start_mib, rss.copies_end_mib, rss.non_map_slope_mib_per_min);
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

  printTargets(result, options, figures);

  std::printf(
      "\nconditions: %zu 7-Scenes frames preloaded, depth %s (%.0f kB), colour jpeg (%.0f kB); %.0f s; cameras %.0f "
      "Hz; segmenters every %.0f-th frame; server %s%s\n",
      data.frames.size(), options.depth.c_str(), data.depth_kb, data.color_kb, result.duration_s, options.camera_hz,
      std::max(1.0, options.camera_hz / options.segmenter_hz), result.after.version.c_str(),
      options.server_cpus.empty() ? "" : (", on CPUs " + options.server_cpus).c_str());
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
