#include "esdf_config.hpp"

#include <string>

namespace semfuse::server {

void addEsdfOptions(CLI::App& app, EsdfConfig& c) {
  auto* group = "Distance field and occupancy grid (--esdf)";
  // --esdf.enabled: the name a YAML `esdf:` section holds it by, beside the field's other keys.
  app.add_flag("--esdf,--esdf.enabled", c.enabled,
               "keep a Euclidean signed distance field of the map (observed free space included) and serve "
               "distance, occupancy_slice, semantic_distance, semantic_slice, segment_check; publish "
               "rt/semfuse/occupancy")
      ->group(group);
  app.add_option("--esdf.max-distance", c.field.max_distance, "metres up to which distances are exact")
      ->group(group)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--esdf.voxel-size", c.field.voxel_size,
                 "the field's voxel edge, metres: a whole multiple of --voxel-size, at most --truncation (0 = the "
                 "coarsest such up to 5 cm); a coarser field costs far less to keep up")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--esdf.min-site-weight", c.field.min_site_weight,
                 "integration weight a surface voxel needs to seed the field")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--esdf.max-slice-cells", c.max_slice_cells, "largest occupancy or semantic slice a query may ask for")
      ->group(group)
      ->capture_default_str();
  app.add_option("--occupancy.rate", c.occupancy_rate_hz,
                 "occupancy grids per second on rt/semfuse/occupancy when the map changed (0 = none)")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--occupancy.min-z", c.occupancy_min_z, "bottom of the height band, metres (world z up)")
      ->group(group)
      ->capture_default_str();
  app.add_option("--occupancy.max-z", c.occupancy_max_z, "top of the height band, metres")
      ->group(group)
      ->capture_default_str();
  app.add_option("--occupancy.inflation", c.occupancy_inflation,
                 "free cells within this many metres of an occupied one are 99")
      ->group(group)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  app.add_option("--occupancy.frame-id", c.occupancy_frame_id, "frame_id of the published grids")
      ->group(group)
      ->capture_default_str();
}

Status validateEsdfConfig(const EsdfConfig& c, double voxel_size, double truncation) {
  if (!c.enabled) return Status::Ok();
  if (Status ok = c.field.validate(voxel_size, truncation); !ok)
    return makeError(ErrorCode::kInvalidArgument, "--esdf: " + ok.error());
  if (!(c.occupancy_max_z >= c.occupancy_min_z))
    return makeError(ErrorCode::kInvalidArgument, "--occupancy.max-z " + std::to_string(c.occupancy_max_z) +
                                                      " is below --occupancy.min-z " +
                                                      std::to_string(c.occupancy_min_z));
  if (c.max_slice_cells == 0) return makeError(ErrorCode::kInvalidArgument, "--esdf.max-slice-cells must be positive");
  return Status::Ok();
}

}  // namespace semfuse::server
