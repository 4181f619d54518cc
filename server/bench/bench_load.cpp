// semfuse-bench load: the whole service at once on loopback DDS (server/app/README.md).
//  - Starts a real semfuse-server with --esdf (default map settings: 1 cm voxels, the default
//    label rule) on its own domain, and stops it with SIGTERM at the end, on error and on Ctrl-C.
//  - Streams preloaded 7-Scenes frames from posed and tracked cameras (2 + 2 at 30 Hz), runs
//    segmenters on some of them (2 at 10 Hz, client::Segmenter with a depth-band labeller that
//    costs about a millisecond), query clients (raycast 640x480 d+n+l at 10 Hz; labels_at,
//    objects, distance at 5 Hz each) and a map follower, all in this process, for --duration.
//  - Reports where every input ended (server status counters), the latency of each stage the
//    server reports, query reply times, CPU per server thread, the server's RSS over time, and the
//    raycast through the server against the library's on the same map with nothing else running.
//  - With --check it exits 1 when an input was lost without a counted reason or a query got no
//    reply (the short ctest run), whatever the timings.
//  The parts are in load/ (scenario, query clients, segmentation function, RSS timeline, input
//  accounting, report) and reuse ingest/ (preloaded frames, camera threads, pose collector, map
//  follower, the server process).
#include <cstdio>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "ingest/bench_server.hpp"
#include "ingest/interrupt.hpp"
#include "ingest/preloaded_frames.hpp"
#include "load/load_options.hpp"
#include "load/load_report.hpp"
#include "load/load_run.hpp"
#include "semfuse/core/malloc_tuning.hpp"

namespace semfuse::bench::load {
namespace {

int runLoadBench(const LoadOptions& options) {
  keepScratchResident();              // the library raycast it times against the server's runs as the server's does
  ingest::installInterruptHandler();  // Ctrl-C: the run ends early, the server is still stopped

  ingest::IngestOptions frames;
  frames.data = options.data;
  frames.frames = options.frames;
  frames.depth = options.depth;
  std::printf("preloading %zu 7-Scenes frames from %s ...\n", options.frames, options.data.c_str());
  std::fflush(stdout);
  Stopwatch load_watch;
  auto data = ingest::preload(frames);
  if (!data) {
    std::fprintf(stderr, "%s\n", data.error().c_str());
    return 2;
  }
  std::printf("  %zu frames in %.1f s; load average %.2f\n", data.value().frames.size(), load_watch.elapsedMs() / 1e3,
              loadAverage());

  std::vector<std::string> server_args{"--esdf"};
  server_args.insert(server_args.end(), options.server_args.begin(), options.server_args.end());
  auto server = ingest::startBenchServer(options.server, options.domain, server_args);
  if (!server) {
    std::fprintf(stderr, "%s\n", server.error().c_str());
    return 2;
  }
  cli::ChildProcess& process = *server.value().process;
  int code = 1;
  try {
    LoadRun run(options, data.value(), static_cast<dds_domainid_t>(server.value().domain));
    auto result = run.run(process.pid());
    if (!result) {
      std::fprintf(stderr, "load bench: %s\n", result.error().c_str());
    } else {
      if (ingest::interrupted()) std::printf("interrupted: partial results\n");
      printLoadReport(result.value(), options, data.value());
      code = 0;
      if (options.check) {
        const std::vector<std::string> failures = checkFailures(result.value());
        for (const auto& failure : failures) std::printf("check FAILED: %s\n", failure.c_str());
        if (failures.empty()) std::printf("check passed: every input integrated or counted, every query answered\n");
        code = failures.empty() ? 0 : 1;
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "load bench: %s\n", e.what());
  }
  const int server_exit = process.stop();
  std::printf("server stopped with SIGTERM, exit code %d\n", server_exit);
  return server_exit == 0 ? code : (code ? code : 1);
}

const bool load_registered = registerBench(
    "load",
    "the whole service on loopback DDS: posed + tracked cameras, segmenters, raycast / labels_at / objects / distance "
    "queries and a map follower at once",
    [](CLI::App& command) {
      auto options = std::make_shared<LoadOptions>();
      command.add_option("--server", options->server, "semfuse-server executable")->capture_default_str();
      command.add_option("--data", options->data, "7-Scenes sequence folder")->capture_default_str();
      command.add_option("--frames", options->frames, "frames to preload (the cameras replay them)")
          ->capture_default_str();
      command.add_option("--depth", options->depth, "depth encoding on the wire")
          ->check(CLI::IsMember({"raw", "png", "rvl"}))
          ->capture_default_str();
      command.add_option("--duration", options->duration_s, "seconds of load")->capture_default_str();
      command.add_option("--camera-rate", options->camera_hz, "frames per second per camera")->capture_default_str();
      command.add_option("--posed-cameras", options->posed_cameras, "cameras that send their poses")
          ->capture_default_str();
      command
          .add_option("--tracked-cameras", options->tracked_cameras,
                      "cameras that send no pose (the server tracks them)")
          ->capture_default_str();
      command.add_option("--segmenters", options->segmenters, "segmenters; segmenter k labels camera k")
          ->capture_default_str();
      command.add_option("--segmenter-rate", options->segmenter_hz, "segmentations per second per segmenter")
          ->capture_default_str();
      command.add_option("--raycast-rate", options->raycast_hz, "raycasts per second (0 = none)")
          ->capture_default_str();
      command
          .add_option("--query-rate", options->query_hz,
                      "labels_at, objects and distance queries per second each (0 = none)")
          ->capture_default_str();
      command.add_option("--query-timeout", options->query_timeout_s, "seconds a query may wait for its reply")
          ->capture_default_str();
      command.add_option("--follow-map", options->follow_map, "run a map follower (as a viewer)")
          ->capture_default_str();
      command.add_option("--domain-id", options->domain, "DDS domain (-1 = from the pid)")->capture_default_str();
      command.add_flag("--check", options->check,
                       "exit 1 when an input was lost without a counted reason or a query got no reply");
      command.add_option("--server-arg", options->server_args,
                         "extra semfuse-server argument, repeatable (e.g. --server-arg=--voxel-size=0.02)");
      return [options] { return runLoadBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench::load
