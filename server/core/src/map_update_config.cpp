#include "map_update_config.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace semfuse::server {

int MapUpdateConfig::stride(double map_voxel, double truncation) const {
  if (!(map_voxel > 0.0)) return 1;
  const double ratio = voxel_size > 0.0 ? std::round(voxel_size / map_voxel)
                                        : std::floor(std::min(kAutoLiveVoxel, truncation) / map_voxel * (1.0 + 1e-9));
  return static_cast<int>(std::clamp(ratio, 1.0, static_cast<double>(kMaxStride)));
}

Status validateMapUpdateConfig(const MapUpdateConfig& c, double map_voxel, double truncation) {
  if (c.voxel_size == 0.0) return Status::Ok();
  const double ratio = c.voxel_size / map_voxel;
  if (!std::isfinite(ratio) || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio || ratio < 1.0 - 1e-6 ||
      std::round(ratio) > MapUpdateConfig::kMaxStride)
    return makeError(ErrorCode::kInvalidArgument, "--map-updates.voxel-size " + std::to_string(c.voxel_size) +
                                                      " m is not 1 to " + std::to_string(MapUpdateConfig::kMaxStride) +
                                                      " times the map's voxel " + std::to_string(map_voxel) + " m");
  if (std::round(ratio) > 1.0 && c.voxel_size > truncation * (1.0 + 1e-6))
    return makeError(ErrorCode::kInvalidArgument, "--map-updates.voxel-size " + std::to_string(c.voxel_size) +
                                                      " m is larger than the truncation " + std::to_string(truncation) +
                                                      " m: surfaces could fall between its samples of the map");
  return Status::Ok();
}

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
  app.add_option(
         "--map-updates.batch-blocks", c.batch_blocks,
         "blocks copied per hold of the map's shared lock, to be meshed after it (the fusion thread waits at most "
         "one batch)")
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
  app.add_option("--map-updates.voxel-size", c.voxel_size,
                 "the live mesh's voxel edge, metres: a whole multiple of --voxel-size, at most --truncation (0 = the "
                 "coarsest such up to 2 cm); the mesh service keeps the map's own")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--map-updates.marker-colors", c.marker_colors, "colours of the ROS 2 markers and cloud")
      ->group(group)
      ->check(CLI::IsMember({"label", "rgb"}))
      ->capture_default_str();
}

}  // namespace semfuse::server
