// semfuse-bench ingest: the server benchmark, end to end over loopback DDS (server/app/README.md).
//  - Starts a real semfuse-server (default map settings, no --map) on its own domain with the
//    loopback profile, and stops it with SIGTERM at the end, on error and on Ctrl-C.
//  - Preloads the 7-Scenes redkitchen frames, encoded once (depth raw 16UC1 or png16, colour
//    JPEG), so that the publishers spend no CPU on codecs during the measurement: on a 2-core
//    host every cycle the bench burns is taken from the server.
//  - For 1, 2 and 4 cameras at 30 Hz each (camera k replays the sequence from an offset of k/N
//    of it, under its own camera_id), one thread per camera publishes with given poses on an
//    absolute schedule, for a fixed duration; then 2 cameras stream while a raycast client
//    queries the map.
//  - Measures the server's targets (every frame of 4 cameras at 30 Hz integrated, publish -> pose
//    p50 <= 30 ms, a raycast under 2 cameras p50 <= 50 ms): frames/s integrated (poses topic and server status), drops
//    and rejections by reason (status counters), publish -> TrackedPose latency (the publish
//    time travels in the frame's header stamp, which the server echoes in the pose), server CPU
//    and RSS (/proc), raycast reply times; plus what tells where the time goes: per-thread CPU of
//    the server and the tracking/integration times the server reports in each TrackedPose.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "msg.h"
#include "semfuse/client/map_client.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/ros_codec.hpp"

namespace semfuse::bench {
namespace {

using Clock = std::chrono::steady_clock;
using FrameMsg = semfuse_msg_dds__Frame_;
using PoseMsg = semfuse_msg_dds__TrackedPose_;

struct IngestOptions {
  std::string server =
#ifdef SEMFUSE_SERVER_EXE
      SEMFUSE_SERVER_EXE;
#else
      "";
#endif
  std::string data = redkitchenDir().string();
  std::size_t frames = 500;
  double duration_s = 10.0;
  double rate_hz = 30.0;
  std::vector<int> cameras{1, 2, 4};
  std::string depth = "raw";
  double raycast_duration_s = 10.0;  // 0 = no raycast phase
  int raycast_period_ms = 100;       // a viewer refreshing at 10 Hz
  int domain = -1;                   // -1 = derived from the pid
  std::vector<std::string> server_args;
};

std::atomic<bool> g_interrupted{false};
void onInterrupt(int /*signal*/) { g_interrupted = true; }

double wallMs(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double, std::milli>(to - from).count();
}

// ---------------------------------------------------------------------------------------------
// The server process. fork + exec rather than posix_spawn so that the child can ask the kernel
// to SIGTERM it when the bench dies (PR_SET_PDEATHSIG): even a killed bench leaves no server.
class ServerProcess {
 public:
  static Result<std::unique_ptr<ServerProcess>> start(std::vector<std::string> args) {
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) return makeError("fork failed");
    if (pid == 0) {  // child: only async-signal-safe calls until exec
      ::prctl(PR_SET_PDEATHSIG, SIGTERM);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    return std::unique_ptr<ServerProcess>(new ServerProcess(pid));
  }
  ~ServerProcess() { stop(); }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  pid_t pid() const { return pid_; }
  bool running() {
    if (exited_) return false;
    if (::waitpid(pid_, &status_, WNOHANG) == 0) return true;
    exited_ = true;
    return false;
  }
  // SIGTERM (the server saves nothing without --map, so it should exit quickly), SIGKILL after
  // 20 s. Returns the exit code, -1 when killed or died from a signal.
  int stop() {
    if (!exited_) {
      ::kill(pid_, SIGTERM);
      for (int waited = 0; waited < 20000 && running(); waited += 10) ::usleep(10000);
      if (!exited_) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, &status_, 0);
        exited_ = true;
        return -1;
      }
    }
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }

 private:
  explicit ServerProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_;
  int status_ = 0;
  bool exited_ = false;
};

// ---------------------------------------------------------------------------------------------
// /proc readings of the server: CPU seconds of the process and of each thread, resident memory.
struct ThreadCpu {
  std::string name;
  double seconds = 0;
};
struct CpuSample {
  Clock::time_point when = Clock::now();
  double process_s = 0;
  std::map<int, ThreadCpu> threads;  // by tid
};

// utime + stime of a /proc/.../stat line, and the comm name. The name is in parentheses and may
// contain spaces, so fields are counted from the last ')'.
std::optional<ThreadCpu> readStat(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return std::nullopt;
  const auto open = line.find('('), close = line.rfind(')');
  if (open == std::string::npos || close == std::string::npos) return std::nullopt;
  std::istringstream fields(line.substr(close + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; fields >> field; ++i) {  // the first field after ')' is field 3 (state)
    if (i == 14) utime = std::stod(field);
    if (i == 15) {
      stime = std::stod(field);
      break;
    }
  }
  static const double ticks = static_cast<double>(::sysconf(_SC_CLK_TCK));
  return ThreadCpu{line.substr(open + 1, close - open - 1), (utime + stime) / ticks};
}

CpuSample sampleCpu(pid_t pid) {
  CpuSample sample;
  const std::string base = "/proc/" + std::to_string(pid);
  if (auto process = readStat(base + "/stat")) sample.process_s = process->seconds;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(base + "/task", ec)) {
    if (auto thread = readStat(entry.path().string() + "/stat"))
      sample.threads[std::stoi(entry.path().filename().string())] = *thread;
  }
  return sample;
}

// A field of /proc/<pid>/status in MiB ("VmRSS:", "VmHWM:"), 0 when unreadable.
double procStatusMiB(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(field, 0) == 0) return std::stod(line.substr(field.size())) / 1024.0;  // kB
  }
  return 0;
}

// Samples VmRSS every 100 ms: the peak during one run, which VmHWM (peak since start) cannot give.
class RssMonitor {
 public:
  explicit RssMonitor(pid_t pid) : pid_(pid), thread_([this] { loop(); }) {}
  ~RssMonitor() {
    running_ = false;
    thread_.join();
  }
  void resetPeak() { peak_ = procStatusMiB(pid_, "VmRSS:"); }
  double peak() const { return peak_; }

 private:
  void loop() {
    while (running_) {
      const double now = procStatusMiB(pid_, "VmRSS:");
      double seen = peak_;
      while (now > seen && !peak_.compare_exchange_weak(seen, now)) {
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  pid_t pid_;
  std::atomic<double> peak_{0};
  std::atomic<bool> running_{true};
  std::thread thread_;
};

// ---------------------------------------------------------------------------------------------
// The frames, encoded once. Each camera thread sends a shallow copy of a message with its own
// camera_id, seq and stamp: the payload buffers are shared and only read by dds_write.
struct Preloaded {
  std::vector<wire::EncodedFrame> frames;
  std::vector<Pose> poses;
  PinholeIntrinsics intrinsics;
  double depth_kb = 0, color_kb = 0;  // mean payload per frame
};

Result<Preloaded> preload(const IngestOptions& options) {
  auto reader = datasets::SevenScenesReader::open(options.data);
  if (!reader) return makeError("7-Scenes: " + reader.error());
  const auto& r = reader.value();
  wire::FrameEncoding encoding;
  encoding.depth = options.depth == "png" ? "png16" : "16UC1";
  encoding.color = "jpeg";
  Preloaded out;
  out.intrinsics = r.intrinsics();
  const std::size_t count = std::min(options.frames, r.count());
  for (std::size_t i = 0; i < count && !g_interrupted; ++i) {
    auto frame = r.load(i);
    if (!frame) return makeError("frame " + std::to_string(i) + ": " + frame.error());
    if (!frame.value().camera_to_world) return makeError("frame " + std::to_string(i) + " has no pose");
    auto encoded = wire::encodeFrame(frame.value(), encoding);
    if (!encoded) return makeError("encode frame " + std::to_string(i) + ": " + encoded.error());
    out.depth_kb += encoded.value().msg().depth._length / 1024.0;
    out.color_kb += encoded.value().msg().color._length / 1024.0;
    out.poses.push_back(*frame.value().camera_to_world);
    out.frames.push_back(std::move(encoded).value());
  }
  if (out.frames.empty()) return makeError("no frames loaded");
  out.depth_kb /= static_cast<double>(out.frames.size());
  out.color_kb /= static_cast<double>(out.frames.size());
  return out;
}

// ---------------------------------------------------------------------------------------------
// Every TrackedPose the server publishes, with the latency from its frame's publish time.
struct PoseRecord {
  std::string camera_id;
  bool integrated = false;
  double latency_ms = 0;
  double server_ms = 0;  // track_ms + integrate_ms: the fusion thread's work on the frame
};

class PoseCollector {
 public:
  explicit PoseCollector(const dds::Participant& participant)
      : topic_(participant, dds::topics::kPoses),
        reader_(topic_, dds::qos::poses()),
        ready_(reader_.handle()),
        waitset_(participant),
        thread_([this] { loop(); }) {}
  ~PoseCollector() {
    running_ = false;
    thread_.join();
  }
  std::vector<PoseRecord> take() {
    std::lock_guard lock(mutex_);
    return std::exchange(records_, {});
  }

 private:
  void loop() {
    waitset_.attach(ready_.handle());
    while (running_) {
      if (auto woke = waitset_.wait(DDS_MSECS(100)); !woke || woke.value().empty()) continue;
      static_cast<void>(reader_.takeLoaned(dds::Reader<PoseMsg>::kMaxBatch, [this](const PoseMsg& pose, const auto&) {
        const double now_ms =
            std::chrono::duration<double, std::milli>(std::chrono::system_clock::now().time_since_epoch()).count();
        const double sent_ms = pose.header.stamp.sec * 1e3 + pose.header.stamp.nanosec * 1e-6;
        std::lock_guard lock(mutex_);
        records_.push_back({wire::stringOf(pose.camera_id), pose.integrated, now_ms - sent_ms,
                            static_cast<double>(pose.track_ms) + pose.integrate_ms});
      }));
    }
  }
  dds::Topic<PoseMsg> topic_;
  dds::Reader<PoseMsg> reader_;
  dds::ReadCondition ready_;
  dds::WaitSet waitset_;
  std::mutex mutex_;
  std::vector<PoseRecord> records_;
  std::atomic<bool> running_{true};
  std::thread thread_;  // last: starts once the members above exist
};

// ---------------------------------------------------------------------------------------------
// One camera: frames first_index, first_index+1, ... (wrapping) at slot times start + n * period.
// A slot that is already over when the previous write returns is skipped, not sent late in a
// burst: a real camera does not queue its frames either.
struct CameraResult {
  std::size_t sent = 0, write_failures = 0, skipped_slots = 0;
  std::vector<double> write_ms;
};

void runCamera(const Preloaded& data, const dds::Writer<FrameMsg>& writer, std::string camera_id,
               std::size_t first_index, Clock::time_point start, Clock::duration period, std::size_t slots,
               CameraResult& result, std::atomic<std::size_t>* current_index) {
  for (std::size_t slot = 0; slot < slots && !g_interrupted; ++slot) {
    const auto due = start + period * static_cast<long>(slot);
    if (Clock::now() > due + period) {
      ++result.skipped_slots;
      continue;
    }
    std::this_thread::sleep_until(due);
    const std::size_t index = (first_index + slot) % data.frames.size();
    FrameMsg msg = data.frames[index].msg();
    msg.camera_id = camera_id.data();
    msg.seq = slot;
    const Stamp now = wire::stampNow();
    msg.header.stamp.sec = now.sec;
    msg.header.stamp.nanosec = now.nanosec;
    Stopwatch write_watch;
    const Status written = writer.write(msg);
    result.write_ms.push_back(write_watch.elapsedMs());
    if (written) {
      ++result.sent;
      if (current_index) current_index->store(index);
    } else {
      ++result.write_failures;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Results of one run and the table.
struct RunResult {
  std::string title;
  int cameras = 0;
  double duration_s = 0;
  std::size_t sent = 0, write_failures = 0, skipped_slots = 0;
  Timings write_ms;
  client::ServerStatus before, after;
  std::vector<PoseRecord> poses;
  double cpu_percent = 0, rss_peak_mib = 0;
  std::vector<std::pair<std::string, double>> top_threads;  // name (tid), CPU %
  double load_start = 0, load_end = 0;
  Timings raycast_ms;
  std::size_t raycast_failures = 0;
  std::string raycast_error;
};

// Per-reason counter deltas, summed over cameras: "queue_full 12, tracking_lost 1" or "0".
std::string counterDelta(const std::vector<client::ReasonCount>& before, const std::vector<client::ReasonCount>& after,
                         uint64_t* total = nullptr) {
  std::map<std::string, int64_t> delta;
  for (const auto& c : after) delta[c.reason] += static_cast<int64_t>(c.count);
  for (const auto& c : before) delta[c.reason] -= static_cast<int64_t>(c.count);
  std::string text;
  uint64_t sum = 0;
  for (const auto& [reason, n] : delta) {
    if (n == 0) continue;
    text += (text.empty() ? "" : ", ") + reason + " " + std::to_string(n);
    sum += static_cast<uint64_t>(std::max<int64_t>(n, 0));
  }
  if (total) *total = sum;
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
  auto integrated = [](const RunResult& run) {
    return static_cast<std::size_t>(
        std::count_if(run.poses.begin(), run.poses.end(), [](const auto& p) { return p.integrated; }));
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
      "integrated/s (poses topic)", [&](const RunResult& r) { return formatNumber(integrated(r) / r.duration_s, 1); },
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
      "server track+integrate ms p50/p95",
      [](const RunResult& r) {
        Timings t;
        for (const auto& p : r.poses) t.add(p.server_ms);
        return t.count() ? formatNumber(t.median(), 1) + " / " + formatNumber(t.p95(), 1) : std::string("-");
      },
      "(from TrackedPose)");
  row(
      "fusion busy: sum(track+integrate) / run",
      [](const RunResult& r) {
        double busy = 0;
        for (const auto& p : r.poses) busy += p.server_ms;
        return formatNumber(busy / (r.duration_s * 10.0), 0) + " %";
      },
      "< 100 %");
  row(
      "server CPU (100 % = 1 core)", [](const RunResult& r) { return formatNumber(r.cpu_percent, 0) + " %"; },
      "of 200 % here");
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

  std::printf("\nserver threads, CPU %% during each run (top 5; 100 %% = 1 core):\n");
  for (const auto& run : runs) {
    std::string line;
    for (const auto& [name, pct] : run.top_threads) line += "  " + name + " " + formatNumber(pct, 0) + "%";
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
      data.frames.size(), options.depth == "png" ? "png16" : "raw 16UC1", data.depth_kb, data.color_kb,
      options.duration_s, options.rate_hz, std::thread::hardware_concurrency());
}

// ---------------------------------------------------------------------------------------------
class IngestBench {
 public:
  IngestBench(const IngestOptions& options, const Preloaded& data, dds_domainid_t domain)
      : options_(options),
        data_(data),
        participant_(domain),
        frame_topic_(participant_, dds::topics::kFrames),
        map_(participant_),
        poses_(participant_) {}

  // Runs every configuration; the server must already be up and `pid` its process.
  int run(pid_t pid) {
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
      if (g_interrupted) break;
      auto result = runOnce(pid, rss, cameras, options_.duration_s, false);
      if (!result) {
        std::fprintf(stderr, "%s\n", result.error().c_str());
        return 1;
      }
      runs.push_back(std::move(result).value());
    }
    std::optional<RunResult> idle;
    if (options_.raycast_duration_s > 0 && !g_interrupted) {
      auto result = runOnce(pid, rss, 2, options_.raycast_duration_s, true);
      if (!result) {
        std::fprintf(stderr, "%s\n", result.error().c_str());
        return 1;
      }
      runs.push_back(std::move(result).value());
      idle = idleRaycasts();  // same map, no camera: what the streaming costs the query
    }
    if (g_interrupted) std::printf("interrupted: partial results\n");
    printResults(runs, options_, data_, idle ? &*idle : nullptr);
    return 0;
  }

 private:
  Result<client::ServerStatus> stats() {
    auto status = map_.stats(std::chrono::seconds(10));
    if (!status) return makeError("stats: " + status.error());
    return std::move(status).value();
  }

  Result<RunResult> runOnce(pid_t pid, RssMonitor& rss, int cameras, double duration_s, bool with_raycast) {
    RunResult run;
    run.cameras = cameras;
    run.duration_s = duration_s;
    run.title = std::to_string(cameras) + (cameras == 1 ? " camera" : " cameras") + (with_raycast ? " + raycast" : "");
    std::printf("running %s for %.0f s ...\n", run.title.c_str(), duration_s);
    std::fflush(stdout);

    if (auto reset = map_.reset(std::chrono::seconds(30)); !reset) return makeError("reset: " + reset.error());
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    poses_.take();  // nothing from before this run
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
                           std::ref(results[static_cast<std::size_t>(k)]), k == 0 ? &camera0_index : nullptr);
    }
    if (with_raycast)
      raycastUntil(start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(duration_s)),
                   camera0_index, run);
    for (auto& t : threads) t.join();
    const CpuSample cpu_end = sampleCpu(pid);
    run.load_end = loadAverage();

    // CPU over the publishing window (the drain below adds at most a few queued frames).
    const double window_s = wallMs(cpu_start.when, cpu_end.when) / 1e3;
    run.cpu_percent = (cpu_end.process_s - cpu_start.process_s) / window_s * 100.0;
    for (const auto& [tid, thread] : cpu_end.threads) {
      const auto was = cpu_start.threads.find(tid);
      const double used = thread.seconds - (was == cpu_start.threads.end() ? 0.0 : was->second.seconds);
      run.top_threads.emplace_back(thread.name + "(" + std::to_string(tid) + ")", used / window_s * 100.0);
    }
    std::sort(run.top_threads.begin(), run.top_threads.end(),
              [](const auto& a, const auto& b) { return a.second > b.second; });
    run.top_threads.resize(std::min<std::size_t>(run.top_threads.size(), 5));

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
    return run;
  }

  Result<client::ServerStatus> drain(uint64_t expected_received) {
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
      if (Clock::now() > deadline || g_interrupted) break;
    }
    return last;
  }

  // Raycasts from where camera 0 was a moment ago (the live view a viewer would show), one every
  // raycast_period_ms, or back to back when a reply takes longer.
  void raycastUntil(Clock::time_point end, const std::atomic<std::size_t>& camera0_index, RunResult& run) {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let the map hold something
    const auto period = std::chrono::milliseconds(options_.raycast_period_ms);
    constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
    for (auto next = Clock::now(); Clock::now() < end && !g_interrupted; next += period) {
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

  RunResult idleRaycasts() {
    RunResult run;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    constexpr uint32_t kLayers = client::kDepthLayer | client::kNormalsLayer | client::kLabelsLayer;
    for (int i = 0; i < 20 && !g_interrupted; ++i) {
      Stopwatch watch;
      auto view = map_.raycast(data_.poses[0], data_.intrinsics, kLayers, std::chrono::seconds(5));
      if (view) run.raycast_ms.add(watch.elapsedMs());
    }
    return run;
  }

  const IngestOptions& options_;
  const Preloaded& data_;
  dds::Participant participant_;
  dds::Topic<FrameMsg> frame_topic_;
  client::MapClient map_;
  PoseCollector poses_;
  std::vector<std::unique_ptr<dds::Writer<FrameMsg>>> writers_;
};

int runIngestBench(const IngestOptions& options) {
  if (options.server.empty() || ::access(options.server.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "semfuse-server not found at '%s' (use --server)\n", options.server.c_str());
    return 2;
  }
  // Ctrl-C ends the runs early; the server is still stopped and partial results printed.
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);

  std::printf("preloading %zu 7-Scenes frames from %s ...\n", options.frames, options.data.c_str());
  std::fflush(stdout);
  Stopwatch load_watch;
  auto data = preload(options);
  if (!data) {
    std::fprintf(stderr, "%s\n", data.error().c_str());
    return 2;
  }
  std::printf("  %zu frames in %.1f s; load average %.2f\n", data.value().frames.size(), load_watch.elapsedMs() / 1e3,
              loadAverage());

  const std::string profile = std::string(SEMFUSE_SOURCE_DIR) + "/deploy/dds/localhost.xml";
  ::setenv("CYCLONEDDS_URI", ("file://" + profile).c_str(), 1);  // before the first participant
  const int domain = options.domain >= 0 ? options.domain : 200 + static_cast<int>(::getpid() % 30);
  std::vector<std::string> args{options.server, "--domain-id", std::to_string(domain), "--dds-profile", profile,
                                "--log-level",  "warn"};
  args.insert(args.end(), options.server_args.begin(), options.server_args.end());
  std::printf("server: %s (domain %d)\n", options.server.c_str(), domain);
  auto server = ServerProcess::start(args);
  if (!server) {
    std::fprintf(stderr, "%s\n", server.error().c_str());
    return 2;
  }
  int code = 1;
  try {
    IngestBench bench(options, data.value(), static_cast<dds_domainid_t>(domain));
    code = bench.run(server.value()->pid());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ingest bench: %s\n", e.what());
  }
  const double hwm = procStatusMiB(server.value()->pid(), "VmHWM:");
  const int server_exit = server.value()->stop();
  std::printf("server VmHWM %.0f MiB; stopped with SIGTERM, exit code %d\n", hwm, server_exit);
  return server_exit == 0 ? code : (code ? code : 1);
}

const bool registered = registerBench(
    "ingest", "semfuse-server over loopback DDS: 1/2/4 cameras at 30 Hz, latency, drops, CPU, raycast under load",
    [](CLI::App& command) {
      auto options = std::make_shared<IngestOptions>();
      command.add_option("--server", options->server, "semfuse-server executable")->capture_default_str();
      command.add_option("--data", options->data, "7-Scenes sequence folder")->capture_default_str();
      command.add_option("--frames", options->frames, "frames to preload (the cameras replay them)")
          ->capture_default_str();
      command.add_option("--duration", options->duration_s, "seconds per run")->capture_default_str();
      command.add_option("--rate", options->rate_hz, "frames per second per camera")->capture_default_str();
      command.add_option("--cameras", options->cameras, "camera counts to run")->delimiter(',')->capture_default_str();
      command.add_option("--depth", options->depth, "depth encoding on the wire")
          ->check(CLI::IsMember({"raw", "png"}))
          ->capture_default_str();
      command
          .add_option("--raycast-duration", options->raycast_duration_s,
                      "seconds of 2 cameras + raycast queries (0 = skip)")
          ->capture_default_str();
      command.add_option("--raycast-period-ms", options->raycast_period_ms, "one raycast every ... ms")
          ->capture_default_str();
      command.add_option("--domain-id", options->domain, "DDS domain (-1 = from the pid)")->capture_default_str();
      command.add_option("--server-arg", options->server_args,
                         "extra semfuse-server argument, repeatable (e.g. --server-arg=--color=false)");
      return [options] { return runIngestBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
