#include "report.hpp"

#include <fmt/format.h>

#include "json_writer.hpp"

namespace semfuse::tools {
namespace {

std::string counterLines(const char* title, const std::vector<client::ReasonCount>& counters) {
  std::string out;
  for (const auto& c : counters) {
    out += fmt::format("  {:<10} {:<28} {:>10}\n", title,
                       c.camera_id.empty() ? c.reason : c.reason + " (" + c.camera_id + ")", c.count);
  }
  return out;
}

std::string countersJson(const std::vector<client::ReasonCount>& counters) {
  std::vector<std::string> items;
  for (const auto& c : counters) {
    items.push_back(
        JsonObject().field("reason", c.reason).field("camera_id", c.camera_id).field("count", c.count).str());
  }
  return jsonArray(items);
}

std::string vec(const Eigen::Vector3d& v) { return fmt::format("{:.3f} {:.3f} {:.3f}", v.x(), v.y(), v.z()); }
std::string vecJson(const Eigen::Vector3d& v) {
  return jsonArray({fmt::format("{:.6g}", v.x()), fmt::format("{:.6g}", v.y()), fmt::format("{:.6g}", v.z())});
}

// [{"camera_id": ..., "seq": ...}, ...]
std::string framesJson(const std::vector<FrameRef>& frames) {
  std::vector<std::string> items;
  for (const FrameRef& f : frames)
    items.push_back(JsonObject().field("camera_id", f.camera_id).field("seq", f.seq).str());
  return jsonArray(items);
}

// The share of posed frames integration passed over: what the cores could not integrate.
std::string skippedShare(uint64_t skipped, uint64_t posed) {
  return posed == 0 || skipped == 0 ? "" : fmt::format(", {:.0f} %", 100.0 * static_cast<double>(skipped) / posed);
}

}  // namespace

std::string labelName(const LabelLegend& legend, LabelId id) {
  if (const LabelInfo* info = legend.find(id)) return info->name;
  return "label " + std::to_string(id);
}

std::string statusTable(const client::ServerStatus& s) {
  std::string out = fmt::format("server {} (version {}), up {:.0f} s\n", s.server_id, s.version, s.uptime_s);
  out +=
      fmt::format("  frames         received {:>8}  posed {:>8} (integrated {}, skipped {}{})  lost {:>6}  queued {}\n",
                  s.frames_received, s.frames_posed, s.frames_integrated, s.frames_skipped,
                  skippedShare(s.frames_skipped, s.frames_posed), s.frames_lost, s.queued_frames);
  out += fmt::format("  segmentations  received {:>8}  integrated {:>8}  pending {}\n", s.segmentations_received,
                     s.segmentations_integrated, s.pending_segmentations);
  out += fmt::format("  map            {} voxels in {} blocks, {:.1f} MiB, voxel {:.3f} m, truncation {:.3f} m\n",
                     s.allocated_voxels, s.allocated_blocks, s.map_bytes / 1048576.0, s.voxel_size, s.truncation);
  if (s.distance_field_revision > 0)
    out += fmt::format("  distance field {}\n",
                       s.distance_field_revision >= s.map_revision
                           ? std::string("current")
                           : fmt::format("{} map revisions behind", s.map_revision - s.distance_field_revision));
  out += fmt::format("  process        {:.1f} MiB resident, history {} frames\n", s.rss_bytes / 1048576.0,
                     s.history_frames);
  out += fmt::format("  map file       {} (last save {}, {:.0f} s ago)\n", s.map_file.empty() ? "-" : s.map_file,
                     s.last_save_ok ? "ok" : "failed or none", s.last_save_age_s);
  out += counterLines("dropped", s.dropped);
  out += counterLines("rejected", s.rejected);
  for (const auto& c : s.cameras) {
    out += fmt::format(
        "  camera {:<12} {:<8} last seq {:>6}  received {:>6}  posed {:>6}  integrated {:>6}  skipped {:>5}  lost "
        "{:>4}  "
        "relocalised {:>3}  {:.1f} Hz{}\n",
        c.camera_id, client::trackingStateName(c.tracking_state), c.last_seq, c.frames_received, c.frames_posed,
        c.frames_integrated, c.frames_skipped, c.frames_lost, c.relocalisations, c.frame_rate_hz,
        c.stale ? "  (stale)" : "");
    if (!c.lost_reason.empty())
      out += fmt::format("         lost for {} frames: {}\n", c.frames_since_lost, c.lost_reason);
  }
  if (!s.stages.empty())
    out += fmt::format("  {:<15}{:>10} {:>10} {:>10} {:>10}\n", "stage, ms", "runs", "p50", "p95", "max");
  for (const auto& t : s.stages)
    out +=
        fmt::format("  {:<15}{:>10} {:>10.2f} {:>10.2f} {:>10.2f}\n", t.stage, t.count, t.p50_ms, t.p95_ms, t.max_ms);
  for (const auto& e : s.last_errors) out += fmt::format("  error  [{}] {}\n", e.source, e.message);
  return out;
}

std::string statusJson(const client::ServerStatus& s) {
  std::vector<std::string> cameras;
  for (const auto& c : s.cameras) {
    cameras.push_back(JsonObject()
                          .field("camera_id", c.camera_id)
                          .field("tracking_state", client::trackingStateName(c.tracking_state))
                          .field("last_seq", c.last_seq)
                          .field("frames_received", c.frames_received)
                          .field("frames_posed", c.frames_posed)
                          .field("frames_integrated", c.frames_integrated)
                          .field("frames_skipped", c.frames_skipped)
                          .field("frames_lost", c.frames_lost)
                          .field("frame_rate_hz", static_cast<double>(c.frame_rate_hz))
                          .field("last_frame_age_s", static_cast<double>(c.last_frame_age_s))
                          .field("stale", c.stale)
                          .field("lost_reason", c.lost_reason)
                          .field("frames_since_lost", c.frames_since_lost)
                          .field("relocalisations", c.relocalisations)
                          .str());
  }
  std::vector<std::string> stages;
  for (const auto& t : s.stages) {
    stages.push_back(JsonObject()
                         .field("stage", t.stage)
                         .field("count", t.count)
                         .field("p50_ms", static_cast<double>(t.p50_ms))
                         .field("p95_ms", static_cast<double>(t.p95_ms))
                         .field("max_ms", static_cast<double>(t.max_ms))
                         .str());
  }
  std::vector<std::string> errors;
  for (const auto& e : s.last_errors) {
    errors.push_back(
        JsonObject().field("stamp", e.stamp_s).field("source", e.source).field("message", e.message).str());
  }
  return JsonObject()
      .field("server_id", s.server_id)
      .field("version", s.version)
      .field("uptime_s", s.uptime_s)
      .field("frames_received", s.frames_received)
      .field("frames_posed", s.frames_posed)
      .field("frames_integrated", s.frames_integrated)
      .field("frames_skipped", s.frames_skipped)
      .field("frames_lost", s.frames_lost)
      .field("segmentations_received", s.segmentations_received)
      .field("segmentations_integrated", s.segmentations_integrated)
      .raw("dropped", countersJson(s.dropped))
      .raw("rejected", countersJson(s.rejected))
      .field("queued_frames", s.queued_frames)
      .field("pending_segmentations", s.pending_segmentations)
      .field("history_frames", s.history_frames)
      .field("map_revision", s.map_revision)
      .field("distance_field_revision", s.distance_field_revision)
      .field("voxel_size", s.voxel_size)
      .field("truncation", s.truncation)
      .field("allocated_voxels", s.allocated_voxels)
      .field("allocated_blocks", s.allocated_blocks)
      .field("map_bytes", s.map_bytes)
      .field("rss_bytes", s.rss_bytes)
      .raw("cameras", jsonArray(cameras))
      .raw("last_errors", jsonArray(errors))
      .field("map_file", s.map_file)
      .field("last_save_ok", s.last_save_ok)
      .field("last_save_age_s", s.last_save_age_s)
      .raw("stages", jsonArray(stages))
      .str();
}

std::string objectsTable(const std::vector<client::ObjectInstance>& objects, const LabelLegend& legend) {
  std::string out =
      fmt::format("{:>5}  {:<16} {:>8} {:>8}  {:>6}  {:<26} {:<26} {:<26} {:>6}  {}\n", "id", "label", "voxels",
                  "area m2", "conf", "centroid", "bbox min", "bbox max", "frames", "seen best by");
  for (const auto& o : objects) {
    const std::string best = o.frames.empty() ? "-" : fmt::format("{}#{}", o.frames[0].camera_id, o.frames[0].seq);
    out += fmt::format("{:>5}  {:<16} {:>8} {:>8.3f}  {:>6.3f}  {:<26} {:<26} {:<26} {:>6}  {}{}\n", o.id,
                       fmt::format("{} ({})", labelName(legend, o.label), o.label), o.voxel_count, o.area_m2,
                       o.mean_confidence, vec(o.centroid), vec(o.bbox_min), vec(o.bbox_max), o.frame_count, best,
                       o.fragment ? "  fragment" : "");
  }
  return out + fmt::format("{} objects\n", objects.size());
}

std::string objectsJson(const std::vector<client::ObjectInstance>& objects, const LabelLegend& legend) {
  std::vector<std::string> items;
  for (const auto& o : objects) {
    items.push_back(
        JsonObject()
            .field("id", o.id)
            .field("label", o.label)
            .field("name", labelName(legend, o.label))
            .field("voxel_count", o.voxel_count)
            .field("mean_confidence", static_cast<double>(o.mean_confidence))
            .raw("centroid", vecJson(o.centroid))
            .raw("bbox_min", vecJson(o.bbox_min))
            .raw("bbox_max", vecJson(o.bbox_max))
            .field("area_m2", o.area_m2)
            .raw("box_center", vecJson(o.box_center))
            .raw("box_half_extents", vecJson(o.box_half_extents))
            .raw("box_rotation_xyzw",
                 jsonArray({fmt::format("{:.6g}", o.box_rotation.x()), fmt::format("{:.6g}", o.box_rotation.y()),
                            fmt::format("{:.6g}", o.box_rotation.z()), fmt::format("{:.6g}", o.box_rotation.w())}))
            .field("fragment", o.fragment)
            .field("frame_count", o.frame_count)
            .raw("frames", framesJson(o.frames))
            .str());
  }
  return jsonArray(items) + "\n";
}

std::string regionTable(const client::RegionSummary& r, const LabelLegend& legend) {
  std::string out = fmt::format("observed {} voxels: {} occupied, {} free (occupancy {:.3f})\n", r.observed_voxels,
                                r.occupied_voxels, r.free_voxels, r.occupancy);
  out += fmt::format("{:<20} {:>14} {:>10}\n", "label", "surface voxels", "area m2");
  for (const auto& h : r.histogram) {
    out += fmt::format("{:<20} {:>14} {:>10.3f}\n", fmt::format("{} ({})", labelName(legend, h.label), h.label),
                       h.surface_voxels, h.area_m2);
  }
  return out;
}

std::string regionJson(const client::RegionSummary& r, const LabelLegend& legend) {
  std::vector<std::string> items;
  for (const auto& h : r.histogram) {
    items.push_back(JsonObject()
                        .field("label", h.label)
                        .field("name", labelName(legend, h.label))
                        .field("surface_voxels", h.surface_voxels)
                        .field("area_m2", h.area_m2)
                        .str());
  }
  return JsonObject()
             .field("observed_voxels", r.observed_voxels)
             .field("occupied_voxels", r.occupied_voxels)
             .field("free_voxels", r.free_voxels)
             .field("occupancy", r.occupancy)
             .raw("histogram", jsonArray(items))
             .str() +
         "\n";
}

std::string samplesTable(const std::vector<Eigen::Vector3d>& points, const std::vector<client::VoxelSample>& samples,
                         const LabelLegend& legend) {
  std::string out =
      fmt::format("{:<26} {:<9} {:<18} {:>6} {:>8} {:>7}\n", "point", "observed", "label", "conf", "tsdf", "weight");
  for (std::size_t i = 0; i < samples.size() && i < points.size(); ++i) {
    const auto& s = samples[i];
    out += fmt::format("{:<26} {:<9} {:<18} {:>6.3f} {:>8.4f} {:>7.1f}\n", vec(points[i]), s.observed ? "yes" : "no",
                       fmt::format("{} ({})", labelName(legend, s.label), s.label), s.confidence, s.tsdf, s.weight);
  }
  return out;
}

std::string samplesJson(const std::vector<Eigen::Vector3d>& points, const std::vector<client::VoxelSample>& samples,
                        const LabelLegend& legend) {
  std::vector<std::string> items;
  for (std::size_t i = 0; i < samples.size() && i < points.size(); ++i) {
    const auto& s = samples[i];
    items.push_back(JsonObject()
                        .raw("point", vecJson(points[i]))
                        .field("observed", s.observed)
                        .field("label", s.label)
                        .field("name", labelName(legend, s.label))
                        .field("confidence", static_cast<double>(s.confidence))
                        .field("tsdf", static_cast<double>(s.tsdf))
                        .field("weight", static_cast<double>(s.weight))
                        .str());
  }
  return jsonArray(items) + "\n";
}

}  // namespace semfuse::tools
