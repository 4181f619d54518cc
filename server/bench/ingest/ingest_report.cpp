#include "ingest_report.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <thread>

namespace semfuse::bench::ingest {
namespace {

// Per-reason counter deltas, summed over cameras: "queue_full 12, tracking_lost 1" or "0".
std::string counterDelta(const std::vector<client::ReasonCount>& before,
                         const std::vector<client::ReasonCount>& after) {
  std::map<std::string, int64_t> delta;
  for (const auto& c : after) delta[c.reason] += static_cast<int64_t>(c.count);
  for (const auto& c : before) delta[c.reason] -= static_cast<int64_t>(c.count);
  std::string text;
  for (const auto& [reason, n] : delta) {
    if (n == 0) continue;
    text += (text.empty() ? "" : ", ") + reason + " " + std::to_string(n);
  }
  return text.empty() ? "0" : text;
}

// Rows of figures with one column per run and the target last.
class Matrix {
 public:
  explicit Matrix(std::vector<std::string> header) { rows_.push_back(std::move(header)); }
  void add(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print() const {
    std::vector<std::size_t> width;
    for (const auto& row : rows_)
      for (std::size_t c = 0; c < row.size(); ++c) {
        width.resize(std::max(width.size(), row.size()));
        width[c] = std::max(width[c], row[c].size());
      }
    for (std::size_t r = 0; r < rows_.size(); ++r) {
      std::string line;
      for (std::size_t c = 0; c < rows_[r].size(); ++c)
        line += rows_[r][c] + std::string(width[c] - rows_[r][c].size() + 2, ' ');
      std::printf("%s\n", line.c_str());
      if (r == 0) std::printf("%s\n", std::string(line.size(), '-').c_str());
    }
  }

 private:
  std::vector<std::vector<std::string>> rows_;
};

}  // namespace

void printResults(const std::vector<RunResult>& runs, const IngestOptions& options, const Preloaded& data,
                  const RunResult* idle_raycast) {
  std::vector<std::string> header{"measure"};
  for (const auto& run : runs) header.push_back(run.title);
  header.push_back("target");
  Matrix m(header);
  auto row = [&](const std::string& what, const std::function<std::string(const RunResult&)>& cell,
                 const std::string& target) {
    std::vector<std::string> r{what};
    for (const auto& run : runs) r.push_back(cell(run));
    r.push_back(target);
    m.add(std::move(r));
  };
  auto posed = [](const RunResult& run) {
    return static_cast<std::size_t>(
        std::count_if(run.poses.begin(), run.poses.end(), [](const auto& p) { return p.posed; }));
  };
  row(
      "frames sent (publishers)",
      [](const RunResult& r) { return std::to_string(r.sent) + " (" + formatNumber(r.sent / r.duration_s, 1) + "/s)"; },
      "30/s per camera");
  row(
      "publisher: slots skipped / write failures",
      [](const RunResult& r) { return std::to_string(r.skipped_slots) + " / " + std::to_string(r.write_failures); },
      "0 / 0");
  row(
      "publisher: write() ms p50/p95",
      [](const RunResult& r) {
        return formatNumber(r.write_ms.median(), 1) + " / " + formatNumber(r.write_ms.p95(), 1);
      },
      "blocks while the server lags");
  row(
      "server received (status)",
      [](const RunResult& r) { return std::to_string(r.after.frames_received - r.before.frames_received); }, "= sent");
  row(
      "posed/s (poses topic)", [&](const RunResult& r) { return formatNumber(posed(r) / r.duration_s, 1); },
      "30 x cameras");
  row(
      "integrated/s (status)",
      [](const RunResult& r) {
        return formatNumber(static_cast<double>(r.after.frames_integrated - r.before.frames_integrated) / r.duration_s,
                            1);
      },
      "30 x cameras");
  row(
      "drops (status, by reason)", [](const RunResult& r) { return counterDelta(r.before.dropped, r.after.dropped); },
      "0");
  row(
      "rejections (status, by reason)",
      [](const RunResult& r) { return counterDelta(r.before.rejected, r.after.rejected); }, "0");
  row(
      "sent but never received",
      [](const RunResult& r) {
        const auto received = r.after.frames_received - r.before.frames_received;
        return std::to_string(static_cast<int64_t>(r.sent) - static_cast<int64_t>(received));
      },
      "0 (DDS keep-last overwrite)");
  row(
      "latency publish->pose ms p50/p95",
      [](const RunResult& r) {
        Timings t;
        for (const auto& p : r.poses) t.add(p.latency_ms);
        return t.count() ? formatNumber(t.median(), 1) + " / " + formatNumber(t.p95(), 1) : std::string("-");
      },
      "p50 <= 30");
  row(
      "server track ms p50/p95",
      [](const RunResult& r) {
        Timings t;
        for (const auto& p : r.poses) t.add(p.track_ms);
        return t.count() ? formatNumber(t.median(), 1) + " / " + formatNumber(t.p95(), 1) : std::string("-");
      },
      "(from TrackedPose)");
  row(
      "server CPU (100 % = 1 core)", [](const RunResult& r) { return formatNumber(r.cpu_percent, 0) + " %"; },
      "of 200 % here");
  if (options.follow_map) {
    row(
        "map update latency ms p50/p95",
        [](const RunResult& r) {
          if (r.update_latency_ms.count() == 0) return std::string("-");
          return formatNumber(r.update_latency_ms.median(), 0) + " / " + formatNumber(r.update_latency_ms.p95(), 0) +
                 " (" + std::to_string(r.map_updates) + " updates)";
        },
        "p50 <= 300 (pose received -> next update with more frames)");
  }
  row(
      "server RSS peak MiB", [](const RunResult& r) { return formatNumber(r.rss_peak_mib, 0); }, "bounded");
  row(
      "raycast 640x480 d+n+l ms p50/p95",
      [](const RunResult& r) {
        if (r.raycast_ms.count() == 0 && r.raycast_failures == 0) return std::string("-");
        return formatNumber(r.raycast_ms.median(), 1) + " / " + formatNumber(r.raycast_ms.p95(), 1) +
               " (n=" + std::to_string(r.raycast_ms.count()) +
               (r.raycast_failures ? ", failed " + std::to_string(r.raycast_failures) : "") + ")";
      },
      "p50 <= 50 (2 cameras)");
  row(
      "load average 1 min start/end",
      [](const RunResult& r) { return formatNumber(r.load_start, 2) + " / " + formatNumber(r.load_end, 2); },
      "2 cores");
  m.print();

  std::printf("\nserver threads by name, CPU %% during each run (from 0.5 %%; 100 %% = 1 core; x N: N threads):\n");
  for (const auto& run : runs) {
    std::string line;
    for (const ThreadCpuShare& t : run.server_threads)
      if (t.percent >= 0.5)
        line += "  " + t.name + (t.threads > 1 ? " x" + std::to_string(t.threads) : "") + " " +
                formatNumber(t.percent, 0) + "%";
    std::printf("  %-22s%s\n", run.title.c_str(), line.c_str());
  }
  if (idle_raycast && idle_raycast->raycast_ms.count())
    std::printf("\nraycast with no camera streaming: %s / %s ms p50/p95 (n=%zu)\n",
                formatNumber(idle_raycast->raycast_ms.median(), 1).c_str(),
                formatNumber(idle_raycast->raycast_ms.p95(), 1).c_str(), idle_raycast->raycast_ms.count());
  for (const auto& run : runs)
    if (!run.raycast_error.empty())
      std::printf("%s: last raycast error: %s\n", run.title.c_str(), run.raycast_error.c_str());
  std::printf(
      "\nconditions: %zu 7-Scenes frames preloaded, depth %s (%.0f kB), colour jpeg (%.0f kB), poses given;"
      " %.0f s per run at %.0f Hz per camera; map reset before each run; %u cores\n",
      data.frames.size(), depthWireEncoding(options.depth).c_str(), data.depth_kb, data.color_kb, options.duration_s,
      options.rate_hz, std::thread::hardware_concurrency());
}

}  // namespace semfuse::bench::ingest
