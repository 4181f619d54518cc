// semfuse-bench ingest: the server benchmark, end to end over loopback DDS (server/app/README.md).
//  - Starts a real semfuse-server (default map settings, no --map) on its own domain with the
//    loopback profile, and stops it with SIGTERM at the end, on error and on Ctrl-C.
//  - Preloads the 7-Scenes redkitchen frames, encoded once (depth raw 16UC1, png16 or rvl, colour
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
//  The parts are in ingest/: /proc readings, the preloaded frames, the camera threads, the pose
//  collector, the runs and the table; the server runs as a cli::ChildProcess.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "ingest/bench_server.hpp"
#include "ingest/ingest_options.hpp"
#include "ingest/ingest_runs.hpp"
#include "ingest/interrupt.hpp"
#include "ingest/preloaded_frames.hpp"
#include "ingest/process_stats.hpp"
#include "semfuse/cli/child_process.hpp"

namespace semfuse::bench::ingest {
namespace {

int runIngestBench(const IngestOptions& options) {
  // Ctrl-C ends the runs early; the server is still stopped and partial results printed.
  installInterruptHandler();

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

  auto server = startBenchServer(options.server, options.domain, options.server_args);
  if (!server) {
    std::fprintf(stderr, "%s\n", server.error().c_str());
    return 2;
  }
  cli::ChildProcess& process = *server.value().process;
  int code = 1;
  try {
    IngestRuns bench(options, data.value(), static_cast<dds_domainid_t>(server.value().domain));
    code = bench.run(process.pid());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ingest bench: %s\n", e.what());
  }
  const double hwm = procStatusMiB(process.pid(), "VmHWM:");
  const int server_exit = process.stop();
  std::printf("server VmHWM %.0f MiB; stopped with SIGTERM, exit code %d\n", hwm, server_exit);
  return server_exit == 0 ? code : (code ? code : 1);
}

const bool ingest_registered = registerBench(
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
          ->check(CLI::IsMember({"raw", "png", "rvl"}))
          ->capture_default_str();
      command
          .add_option("--raycast-duration", options->raycast_duration_s,
                      "seconds of 2 cameras + raycast queries (0 = skip)")
          ->capture_default_str();
      command.add_option("--raycast-period-ms", options->raycast_period_ms, "one raycast every ... ms")
          ->capture_default_str();
      command.add_option("--domain-id", options->domain, "DDS domain (-1 = from the pid)")->capture_default_str();
      command.add_flag("--follow-map", options->follow_map,
                       "follow the live mesh (client::MapFollower) during the runs: the server's CPU with map "
                       "updates, and the update latency");
      command.add_option("--server-arg", options->server_args,
                         "extra semfuse-server argument, repeatable (e.g. --server-arg=--color=false)");
      return [options] { return runIngestBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench::ingest
