#pragma once
// The command line of `semfuse-bench load` (bench_load.cpp declares the flags).
#include <cstddef>
#include <string>
#include <vector>

#include "ingest/ingest_options.hpp"

namespace semfuse::bench::load {

// What runs at once: one robot (a tracked camera, its segmenter, light queries, a map follower)
// or the full service (posed and tracked cameras, two segmenters, queries at video rates).
enum class Scenario { kRobot, kFull };

struct LoadOptions {
  Scenario scenario = Scenario::kFull;
  std::string server = ingest::IngestOptions{}.server;
  std::string server_cpus;     // taskset's CPU list for the server ("" = every core)
  bool compare_cores = false;  // the run twice: the server on CPU 0 alone, then on every core
  std::string data = redkitchenDir().string();
  std::size_t frames = 500;  // preloaded 7-Scenes frames the cameras replay
  std::string depth = "raw";
  double duration_s = 60.0;
  double camera_hz = 30.0;
  int posed_cameras = 2;    // cameras that send their poses
  int tracked_cameras = 2;  // cameras that send none: the server tracks them
  int segmenters = 2;       // segmenter k labels camera k's frames, posed and tracked ones alternating
  double segmenter_hz = 10.0;
  double raycast_hz = 10.0;  // 640x480 depth + normal + label from where camera 0 is
  double query_hz = 5.0;     // labels_at, objects and distance each
  // The objects query accepts those grouped in the background from a map this many seconds old, as
  // a robot that wants them now rather than exact to the last frame would (0 = the map as it is).
  double objects_max_age_s = 2.0;
  bool follow_map = true;  // one client::MapFollower, as a viewer
  double query_timeout_s = 10.0;
  int domain = -1;  // -1 = derived from the pid
  bool check = false;
  std::vector<std::string> server_args;
};

}  // namespace semfuse::bench::load
