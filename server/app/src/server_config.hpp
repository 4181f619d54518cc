#pragma once
// Everything the server can be told, with defaults that work for one 640x480 RGB-D camera at
// room scale. Filled from a YAML file (--config) and command-line flags, flags winning.
#include <cstdint>
#include <string>
#include <vector>

#include <CLI/App.hpp>

#include "ros_config.hpp"

namespace semfuse::server {

struct ServerConfig {
  // DDS
  uint32_t domain_id = 0;
  std::string dds_profile;  // Cyclone XML file; else CYCLONEDDS_URI / Cyclone's defaults
  std::string server_id = "semfuse";

  // Map
  double voxel_size = 0.01;
  double truncation = 0.04;
  float max_weight = 64.0f;
  float max_label_score = 0.0f;      // 0 = the volume library's default W_clamp
  std::string label_rule = "bayes";  // label fusion rule; the winner of docs/eval (paper's: evidence)
  float min_depth = 0.1f;
  float max_depth = 5.0f;
  bool integrate_color = true;
  std::string legend = "ade20k";  // built-in name or a YAML legend file
  std::vector<uint16_t> background_labels;

  // Persistence
  std::string map_file;  // resume from it, autosave to it
  double autosave_period_s = 30.0;

  // Ingest limits
  size_t queue_per_camera = 4;
  size_t history_frames = 120;
  size_t history_megabytes = 512;
  size_t pending_segmentations = 64;
  double pending_timeout_s = 10.0;

  // Tracking
  bool refine_given_poses = false;

  // Queries
  uint32_t max_raycast_pixels = 2048u * 2048u;
  uint32_t mesh_chunk_bytes = 4u << 20;

  // Status
  double status_period_s = 1.0;
  double camera_stale_after_s = 3.0;

  // ROS 2 standard topics as input, /tf as output (--ros-ingest, YAML section `ros:`)
  RosIngestConfig ros;
};

// Declares every option on `app` (documented for --help), bound to `config`.
void addServerOptions(CLI::App& app, ServerConfig& config);

}  // namespace semfuse::server
