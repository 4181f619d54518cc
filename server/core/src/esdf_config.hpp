#pragma once
// Options of the distance field (--esdf) and of the occupancy grid topic: whether the server keeps
// an ESDF, how far it measures, and the band and rate of the 2D grid it publishes for navigation
// stacks. Flags --esdf, --esdf.max-distance, --occupancy.rate, ...; in YAML `esdf: true` and the
// sections `esdf:` and `occupancy:`.
#include <cstdint>
#include <string>

#include <CLI/App.hpp>

#include "semfuse/esdf/esdf_params.hpp"

namespace semfuse::server {

struct EsdfConfig {
  // Off by default: with free space the field costs memory for every observed voxel (about 8
  // bytes each plus the tree; a room at 1 cm is tens of millions of voxels) and a thread.
  bool enabled = false;
  esdf::EsdfParams field;

  // rt/semfuse/occupancy (nav_msgs/OccupancyGrid): the columns within [min_z, max_z] of the
  // whole observed extent, published at most `rate` times a second when the field changed
  // (0 = never), transient-local like a map server's /map.
  double occupancy_rate_hz = 1.0;
  double occupancy_min_z = 0.1;
  double occupancy_max_z = 1.0;
  double occupancy_inflation = 0.0;
  std::string occupancy_frame_id = "map";

  // The largest slice a query may ask for (cells), as --max-raycast-pixels bounds raycasts.
  uint64_t max_slice_cells = uint64_t{4096} * 4096;
};

// Declares --esdf, --esdf.* and --occupancy.* on `app`.
void addEsdfOptions(CLI::App& app, EsdfConfig& config);

// The checks the options cannot express alone (max_z >= min_z, the field's parameters against the
// map's voxel size and truncation); errors name the flag.
Status validateEsdfConfig(const EsdfConfig& config, double voxel_size, double truncation);

}  // namespace semfuse::server
