#pragma once
// semfuse-query's subcommands for the distance field (servers started with --esdf): distance,
// occupancy (PNG + map_server YAML), semantic-distance, semantic-slice, segment-check.
#include <chrono>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "semfuse/client/map_client.hpp"
#include "semfuse/core/legend.hpp"

namespace semfuse::tools {

struct DistanceOptions {
  std::vector<double> points;       // X Y Z per point
  std::vector<std::string> labels;  // ids or names of the legend
  double z_min = 0.1, z_max = 1.0;  // occupancy band
  std::vector<double> min, max;     // X Y box corners
  double inflation = 0.0;
  double z = 0.5;                // semantic slice height
  double resolution = 0.05;      // semantic slice cell
  std::vector<double> from, to;  // segment ends, X Y Z each (repeated)
  double radius = 0.0;
  std::string out;
  bool json = false;
};

class DistanceCommands {
 public:
  // Declares the subcommands on `app`, bound to `options`.
  DistanceCommands(CLI::App& app, DistanceOptions& options);
  bool parsed() const;
  // Runs the parsed one; `legend` gives label names (the server's, fetched when first needed).
  int run(client::MapClient& map, std::chrono::milliseconds timeout,
          const std::function<const LabelLegend&()>& legend) const;

 private:
  int distance(client::MapClient& map, std::chrono::milliseconds timeout) const;
  int occupancy(client::MapClient& map, std::chrono::milliseconds timeout) const;
  int semanticDistance(client::MapClient& map, std::chrono::milliseconds timeout, const LabelLegend& legend) const;
  int semanticSlice(client::MapClient& map, std::chrono::milliseconds timeout, const LabelLegend& legend) const;
  int segmentCheck(client::MapClient& map, std::chrono::milliseconds timeout) const;

  DistanceOptions& o_;
  CLI::App* distance_ = nullptr;
  CLI::App* occupancy_ = nullptr;
  CLI::App* semantic_distance_ = nullptr;
  CLI::App* semantic_slice_ = nullptr;
  CLI::App* segment_check_ = nullptr;
};

// A grid as map_server's PNG (first row = largest y; free 254, occupied 0, inflated 100, unknown
// 205) and its YAML beside it (image, resolution, origin, thresholds), as Nav2 loads them.
Status writeOccupancyMap(const client::OccupancyGrid& grid, const std::string& png_path);

}  // namespace semfuse::tools
