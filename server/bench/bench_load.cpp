// semfuse-bench load: the whole service at once on loopback DDS (server/app/README.md).
//  - Starts a real semfuse-server with --esdf (default map settings: 1 cm voxels, the default
//    label rule) on its own domain, and stops it with SIGTERM at the end, on error and on Ctrl-C.
//  - Streams preloaded 7-Scenes frames from posed and tracked cameras at 30 Hz, runs segmenters on
//    some of them (client::Segmenter with a depth-band labeller that costs about a millisecond),
//    query clients (raycast 640x480 d+n+l; labels_at, objects, distance) and a map follower, all in
//    this process, for --duration. --scenario robot is one robot (1 tracked camera, 1 segmenter at
//    10 Hz, raycasts at 2 Hz, the other queries at 1 Hz); full (the default) is 2 posed + 2 tracked
//    cameras, 2 segmenters, raycasts at 10 Hz and queries at 5 Hz.
//  - Reports where every input ended (server status counters: posed, integrated, skipped, dropped),
//    per camera the pose latency and the share of integrations (fairness), the latency of each
//    stage the server reports, query reply times, CPU per server thread and frames per core, the
//    server's RSS over time, and the raycast through the server against the library's on the same
//    map with nothing else running; the targets of the scenario beside the figures.
//  - --compare-cores runs it twice, the server pinned to CPU 0 and then on every core (taskset).
//  - With --check it exits 1 when an input was lost without a counted reason or a query got no
//    reply (the short ctest run), whatever the timings.
//  The parts are in load/ (scenario, query clients, segmentation function, RSS timeline, input
//  accounting, report) and reuse ingest/ (preloaded frames, camera threads, pose collector, map
//  follower, the server process).
#include <cstdio>
#include <exception>
#include <map>
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

// The load, once: the server started for it (on options.server_cpus), its report printed.
Result<LoadResult> runOnce(const LoadOptions& options, const ingest::Preloaded& data, bool print) {
  std::vector<std::string> server_args{"--esdf"};
  server_args.insert(server_args.end(), options.server_args.begin(), options.server_args.end());
  auto server = ingest::startBenchServer(options.server, options.domain, server_args, options.server_cpus);
  if (!server) return makeError(server.error());
  cli::ChildProcess& process = *server.value().process;
  Result<LoadResult> result = makeError("the run did not finish");
  try {
    LoadRun run(options, data, static_cast<dds_domainid_t>(server.value().domain));
    result = run.run(process.pid());
    if (result && print) {
      if (ingest::interrupted()) std::printf("interrupted: partial results\n");
      printLoadReport(result.value(), options, data);
    }
  } catch (const std::exception& e) {
    result = makeError(e.what());
  }
  const int server_exit = process.stop();
  std::printf("server stopped with SIGTERM, exit code %d\n", server_exit);
  if (result && server_exit != 0) return makeError("the server exited with code " + std::to_string(server_exit));
  return result;
}

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

  if (options.compare_cores) {
    // One core against all of them, the same load on the same frames: how the server scales.
    LoadOptions pinned = options;
    pinned.server_cpus = "0";
    std::printf("\n=== the server pinned to CPU 0 ===\n");
    auto one = runOnce(pinned, data.value(), true);
    if (!one) {
      std::fprintf(stderr, "load bench: %s\n", one.error().c_str());
      return 1;
    }
    std::printf("\n=== the server on every core ===\n");
    LoadOptions all = options;
    all.server_cpus.clear();
    auto every = runOnce(all, data.value(), true);
    if (!every) {
      std::fprintf(stderr, "load bench: %s\n", every.error().c_str());
      return 1;
    }
    printCoreComparison(one.value(), every.value());
    return 0;
  }

  auto result = runOnce(options, data.value(), true);
  if (!result) {
    std::fprintf(stderr, "load bench: %s\n", result.error().c_str());
    return 1;
  }
  if (!options.check) return 0;
  const std::vector<std::string> failures = checkFailures(result.value());
  for (const auto& failure : failures) std::printf("check FAILED: %s\n", failure.c_str());
  if (failures.empty()) std::printf("check passed: every input integrated or counted, every query answered\n");
  return failures.empty() ? 0 : 1;
}

// The scenario's cameras, segmenters and query rates, for the options the command line left out.
struct ScenarioOptions {
  CLI::Option *posed, *tracked, *segmenters, *raycast, *queries;
};

void applyScenario(LoadOptions& o, const ScenarioOptions& given) {
  const bool robot = o.scenario == Scenario::kRobot;
  if (given.posed->count() == 0) o.posed_cameras = robot ? 0 : 2;
  if (given.tracked->count() == 0) o.tracked_cameras = robot ? 1 : 2;
  if (given.segmenters->count() == 0) o.segmenters = robot ? 1 : 2;
  if (given.raycast->count() == 0) o.raycast_hz = robot ? 2.0 : 10.0;
  if (given.queries->count() == 0) o.query_hz = robot ? 1.0 : 5.0;
}

const bool load_registered = registerBench(
    "load",
    "the whole service on loopback DDS: posed + tracked cameras, segmenters, raycast / labels_at / objects / distance "
    "queries and a map follower at once",
    [](CLI::App& command) {
      auto options = std::make_shared<LoadOptions>();
      const std::map<std::string, Scenario> scenarios{{"robot", Scenario::kRobot}, {"full", Scenario::kFull}};
      command
          .add_option("--scenario", options->scenario,
                      "robot: 1 tracked camera, its segmenter, raycasts at 2 Hz, the other queries at 1 Hz; full: 2 "
                      "posed + 2 tracked cameras, 2 segmenters, raycasts at 10 Hz, queries at 5 Hz (the flags below "
                      "change either)")
          ->transform(CLI::CheckedTransformer(scenarios, CLI::ignore_case))
          ->default_str("full");
      command.add_option("--server", options->server, "semfuse-server executable")->capture_default_str();
      command.add_option("--server-cpus", options->server_cpus, "CPU list the server runs on (taskset -c), e.g. 0");
      command.add_flag("--compare-cores", options->compare_cores,
                       "run twice, the server pinned to CPU 0 and then on every core, and compare throughput");
      command.add_option("--data", options->data, "7-Scenes sequence folder")->capture_default_str();
      command.add_option("--frames", options->frames, "frames to preload (the cameras replay them)")
          ->capture_default_str();
      command.add_option("--depth", options->depth, "depth encoding on the wire")
          ->check(CLI::IsMember({"raw", "png", "rvl"}))
          ->capture_default_str();
      command.add_option("--duration", options->duration_s, "seconds of load")->capture_default_str();
      command.add_option("--camera-rate", options->camera_hz, "frames per second per camera")->capture_default_str();
      ScenarioOptions scenario;
      scenario.posed = command.add_option("--posed-cameras", options->posed_cameras, "cameras that send their poses");
      scenario.tracked = command.add_option("--tracked-cameras", options->tracked_cameras,
                                            "cameras that send no pose (the server tracks them)");
      scenario.segmenters =
          command.add_option("--segmenters", options->segmenters, "segmenters; segmenter k labels camera k");
      command.add_option("--segmenter-rate", options->segmenter_hz, "segmentations per second per segmenter")
          ->capture_default_str();
      scenario.raycast = command.add_option("--raycast-rate", options->raycast_hz, "raycasts per second (0 = none)");
      scenario.queries = command.add_option("--query-rate", options->query_hz,
                                            "labels_at, objects and distance queries per second each (0 = none)");
      command
          .add_option("--objects-max-age", options->objects_max_age_s,
                      "seconds: the objects query takes those the server grouped in the background from a map "
                      "this old (0 = grouped from the map as it is, on the query)")
          ->capture_default_str()
          ->check(CLI::Range(0.0, 60.0));
      command.add_option("--query-timeout", options->query_timeout_s, "seconds a query may wait for its reply")
          ->capture_default_str();
      command.add_option("--follow-map", options->follow_map, "run a map follower (as a viewer)")
          ->capture_default_str();
      command.add_option("--domain-id", options->domain, "DDS domain (-1 = from the pid)")->capture_default_str();
      command.add_flag("--check", options->check,
                       "exit 1 when an input was lost without a counted reason or a query got no reply");
      command.add_option("--server-arg", options->server_args,
                         "extra semfuse-server argument, repeatable (e.g. --server-arg=--voxel-size=0.02)");
      return [options, scenario] {
        applyScenario(*options, scenario);
        return runLoadBench(*options);
      };
    });

}  // namespace
}  // namespace semfuse::bench::load
