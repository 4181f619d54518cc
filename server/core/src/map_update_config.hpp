#pragma once
// Options of the live mesh (--map-updates.*; YAML section `map-updates:`): how often the server
// publishes the blocks whose mesh changed on rt/semfuse/map_updates (and as ROS 2 markers and a
// point cloud), how large a sample or a map_blocks page may be, and how the map is read.
#include <cstdint>
#include <string>

#include <CLI/App.hpp>

namespace semfuse::server {

struct MapUpdateConfig {
  double rate_hz = 2.0;              // update rounds per second; 0 = no live mesh and no map_blocks service
  uint32_t sample_bytes = 4u << 20;  // an update larger than this is published in parts
  uint32_t page_bytes = 4u << 20;    // a map_blocks reply's bound when the request names none
  // Blocks meshed per hold of the map's shared lock: the fusion thread waits at most for one batch.
  uint32_t batch_blocks = 256;
  // With no reader of the updates, markers or cloud and no map_blocks request for this long, the
  // server stops following the map (it costs nothing then) and catches up when one comes.
  double idle_after_s = 10.0;
  double cloud_period_s = 2.0;          // rt/semfuse/map_cloud at most this often (0 = never)
  std::string marker_colors = "label";  // markers and cloud coloured by "label" or "rgb"
};

// Declares --map-updates.* on `app`.
void addMapUpdateOptions(CLI::App& app, MapUpdateConfig& config);

}  // namespace semfuse::server
