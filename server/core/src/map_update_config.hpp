#pragma once
// Options of the live mesh (--map-updates.*; YAML section `map-updates:`): how often the server
// publishes the blocks whose mesh changed on rt/semfuse/map_updates (and as ROS 2 markers and a
// point cloud), how large a sample or a map_blocks page may be, and how the map is read.
#include <cstdint>
#include <string>

#include <CLI/App.hpp>

#include "semfuse/core/result.hpp"

namespace semfuse::server {

struct MapUpdateConfig {
  double rate_hz = 2.0;              // update rounds per second; 0 = no live mesh and no map_blocks service
  uint32_t sample_bytes = 4u << 20;  // an update larger than this is published in parts
  uint32_t page_bytes = 4u << 20;    // a map_blocks reply's bound when the request names none
  // Blocks whose voxels are copied per hold of the map's shared lock (they are meshed after it):
  // the fusion thread waits at most for one batch, and a round waits for the lock once per batch.
  uint32_t batch_blocks = 2048;
  // With no reader of the updates, markers or cloud and no map_blocks request for this long, the
  // server stops following the map (it costs nothing then) and catches up when one comes.
  double idle_after_s = 10.0;
  double cloud_period_s = 2.0;          // rt/semfuse/map_cloud at most this often (0 = never)
  std::string marker_colors = "label";  // markers and cloud coloured by "label" or "rgb"
  // The live mesh's voxel edge, metres: a whole multiple of the map's (0 = the coarsest such up to
  // kAutoLiveVoxel and the truncation). A live view needs no finer surface than a screen shows,
  // and each doubling cuts the meshing work about four times; the mesh service stays at the
  // map's own resolution.
  double voxel_size = 0.0;
  static constexpr double kAutoLiveVoxel = 0.02;
  static constexpr int kMaxStride = 8;

  // Map voxels per live mesh voxel, for a map of this voxel size and truncation.
  int stride(double map_voxel, double truncation) const;
};

// Declares --map-updates.* on `app`.
void addMapUpdateOptions(CLI::App& app, MapUpdateConfig& config);

// Refuses a live mesh voxel that is not a whole multiple of the map's (1 to kMaxStride times), or
// wider than the truncation, where surfaces could fall between its samples.
Status validateMapUpdateConfig(const MapUpdateConfig& config, double map_voxel, double truncation);

}  // namespace semfuse::server
