#pragma once
// Everything the server can be told, with defaults that work for one 640x480 RGB-D camera at
// room scale. Filled from a YAML file (--config) and command-line flags, flags winning. The map's
// parameters, the fusion loop's and the queries' limits are their users' own structs: their
// defaults are declared there, and the map's flags come from its field table
// (volume_param_table.hpp).
#include <chrono>
#include <cstdint>
#include <string>

#include <CLI/App.hpp>

#include "esdf_config.hpp"
#include "fusion_limits.hpp"
#include "map_update_config.hpp"
#include "query_limits.hpp"
#include "ros_config.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/tracking/tracker_params.hpp"
#include "semfuse/volume/volume_params.hpp"

namespace semfuse::server {

// How long a camera stays behind (its oldest frame over the maximum wait, not caught up since)
// before its newest frame is fused instead, in multiples of the maximum wait: long enough for the
// backlog of a hiccup to drain (frame_queue.hpp).
inline constexpr int kBacklogTimePerMaxWait = 5;

struct ServerConfig {
  // DDS
  uint32_t domain_id = 0;
  std::string dds_profile;  // Cyclone XML file; else CYCLONEDDS_URI / Cyclone's defaults
  std::string server_id = "semfuse";

  // Map: every volume parameter that has a flag; the label count and the legend's background
  // labels are filled in from the legend (serverVolumeParams).
  volume::VolumeParams volume;
  std::string legend = "ade20k";  // built-in name or a YAML legend file

  // Persistence
  std::string map_file;  // resume from it, autosave to it
  double autosave_period_s = 30.0;

  // Ingest limits
  size_t queue_per_camera = 4;
  // A camera whose oldest queued frame waited longer than this, and that has not caught up for
  // kBacklogTimePerMaxWait times as long, has its newest fused instead (0 = off; frame_queue.hpp).
  double max_queue_wait_s = 0.1;
  FusionLimits fusion;

  // Tracking
  bool refine_given_poses = false;
  // Weight of the photometric term of cameras without poses (tracking::TrackerParams::color_weight);
  // 0 for sensors whose colour is not registered to their depth (7-Scenes), where it biases poses.
  float track_color_weight = tracking::TrackerParams{}.color_weight;

  // Queries
  QueryLimits queries;
  // Background updates of the objects per second while the map changes and somebody wants them
  // (objects_refresher.hpp); 0 = the objects are grouped on queries only.
  double objects_rate_hz = 1.0;

  // Status
  double status_period_s = 1.0;
  double camera_stale_after_s = 3.0;

  // ROS 2 standard topics as input, /tf as output (--ros-ingest, YAML section `ros:`)
  RosIngestConfig ros;

  // The live mesh for viewers, RViz and Foxglove (--map-updates.*, YAML section `map-updates:`)
  MapUpdateConfig map_updates;
  // The distance field and the occupancy grid topic (--esdf, sections `esdf:` and `occupancy:`)
  EsdfConfig esdf;
};

// Declares every option on `app` (documented for --help), bound to `config`.
void addServerOptions(CLI::App& app, ServerConfig& config);

// The label legend the server runs with: --legend, with --background-labels added to its own.
Result<LabelLegend> serverLegend(const ServerConfig& config);

// The volume the server builds: config.volume with the label count and the background labels of
// `legend` (serverLegend's). Errors name the flag to change.
Result<volume::VolumeParams> serverVolumeParams(const ServerConfig& config, const LabelLegend& legend);

// --max-queue-wait as a duration.
std::chrono::steady_clock::duration frameQueueWait(const ServerConfig& config);

}  // namespace semfuse::server
