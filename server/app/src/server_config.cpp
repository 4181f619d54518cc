#include "server_config.hpp"

namespace semfuse::server {

void addServerOptions(CLI::App& app, ServerConfig& c) {
  auto* dds = "DDS";
  app.add_option("--domain-id", c.domain_id, "DDS domain id")->group(dds)->capture_default_str();
  app.add_option("--dds-profile", c.dds_profile,
                 "Cyclone DDS XML profile (e.g. deploy/dds/localhost.xml); default: $CYCLONEDDS_URI")
      ->group(dds);
  app.add_option("--server-id", c.server_id, "name reported in status")->group(dds)->capture_default_str();

  auto* map = "Map";
  app.add_option("--voxel-size", c.voxel_size, "voxel edge, metres")
      ->group(map)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--truncation", c.truncation, "TSDF truncation distance, metres")
      ->group(map)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-weight", c.max_weight, "TSDF weight clamp")
      ->group(map)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--max-label-score", c.max_label_score, "label score clamp W_clamp (0 = library default)")
      ->group(map)
      ->capture_default_str();
  app.add_option("--label-rule", c.label_rule,
                 "label fusion: bayes (top-5 log-probabilities), majority (top-5 counts) or evidence "
                 "(the paper's Algorithm 1); see docs/eval")
      ->group(map)
      ->capture_default_str()
      ->check(CLI::IsMember({"evidence", "majority", "bayes"}));
  app.add_option("--min-depth", c.min_depth, "ignore depth below, metres")->group(map)->capture_default_str();
  app.add_option("--max-depth", c.max_depth, "ignore depth beyond, metres")->group(map)->capture_default_str();
  app.add_option("--color", c.integrate_color, "fuse colour")->group(map)->capture_default_str();
  app.add_option("--legend", c.legend, "label legend: ade20k, voc, nyu40, synthetic or a YAML file")
      ->group(map)
      ->capture_default_str();
  app.add_option("--background-labels", c.background_labels,
                 "label ids that never change a voxel (added to the legend's own)")
      ->group(map);

  auto* files = "Persistence";
  app.add_option("--map", c.map_file, "map file (.vdb): resumed from when it exists, autosaved to")->group(files);
  app.add_option("--autosave-period", c.autosave_period_s, "seconds between autosaves (0 = only on exit)")
      ->group(files)
      ->capture_default_str();

  auto* limits = "Ingest";
  app.add_option("--queue-per-camera", c.queue_per_camera, "frames queued per camera; when full the oldest is dropped")
      ->group(limits)
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--history-frames", c.history_frames, "frames kept for late segmentations")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--history-megabytes", c.history_megabytes, "memory bound of the frame history")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--pending-segmentations", c.pending_segmentations, "segmentations that may wait for their frame")
      ->group(limits)
      ->capture_default_str();
  app.add_option("--pending-timeout", c.pending_timeout_s, "seconds a segmentation waits for its frame")
      ->group(limits)
      ->capture_default_str();

  auto* tracking = "Tracking";
  app.add_option("--refine-poses", c.refine_given_poses, "refine poses that come with frames by SDF alignment")
      ->group(tracking)
      ->capture_default_str();

  auto* queries = "Queries";
  app.add_option("--max-raycast-pixels", c.max_raycast_pixels, "largest raycast image (width*height)")
      ->group(queries)
      ->capture_default_str();
  app.add_option("--mesh-chunk-bytes", c.mesh_chunk_bytes, "PLY bytes per mesh reply")
      ->group(queries)
      ->capture_default_str();

  auto* status = "Status";
  app.add_option("--status-period", c.status_period_s, "seconds between status messages")
      ->group(status)
      ->capture_default_str();
  app.add_option("--stale-after", c.camera_stale_after_s, "a camera silent this long is reported stale")
      ->group(status)
      ->capture_default_str();

  addRosOptions(app, c.ros);
}

}  // namespace semfuse::server
