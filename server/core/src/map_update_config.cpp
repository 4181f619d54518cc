#include "map_update_config.hpp"

namespace semfuse::server {

void addMapUpdateOptions(CLI::App& app, MapUpdateConfig& c) {
  auto* group = "Live mesh (rt/semfuse/map_updates, map_blocks, ROS 2 markers and cloud)";
  app.add_option("--map-updates.rate", c.rate_hz,
                 "map updates per second: the mesh of the blocks that changed (0 = none, and no map_blocks)")
      ->group(group)
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app.add_option("--map-updates.sample-bytes", c.sample_bytes, "an update larger than this goes out in parts")
      ->group(group)
      ->check(CLI::Range(uint32_t{1} << 16, uint32_t{1} << 30))
      ->capture_default_str();
  app.add_option("--map-updates.page-bytes", c.page_bytes, "map_blocks reply size when the request names none")
      ->group(group)
      ->check(CLI::Range(uint32_t{1} << 16, uint32_t{1} << 30))
      ->capture_default_str();
  app.add_option("--map-updates.batch-blocks", c.batch_blocks,
                 "blocks meshed per hold of the map's shared lock (the fusion thread waits at most one batch)")
      ->group(group)
      ->check(CLI::Range(1u, 1u << 20))
      ->capture_default_str();
  app.add_option("--map-updates.idle-after", c.idle_after_s,
                 "seconds without readers or map_blocks requests after which the mesh is not followed")
      ->group(group)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--map-updates.cloud-period", c.cloud_period_s,
                 "seconds between point clouds of the surface on rt/semfuse/map_cloud (0 = none)")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--map-updates.marker-colors", c.marker_colors, "colours of the ROS 2 markers and cloud")
      ->group(group)
      ->check(CLI::IsMember({"label", "rgb"}))
      ->capture_default_str();
}

}  // namespace semfuse::server
