#include "input_accounting.hpp"

#include <algorithm>
#include <set>

namespace semfuse::bench::load {
namespace {

// The reasons under which the server counts a frame, and those under which it counts a
// segmentation (server/core/src/server_state.hpp).
const std::set<std::string> kFrameDrops{"queue_full", "queue_stale", "sequence_gap", "tracking_lost", "map_replaced"};
const std::set<std::string> kFrameRejections{"invalid_frame", "integration_failed"};
const std::set<std::string> kSegmentationDrops{"frame_dropped", "pending_full", "segmentation_timeout", "labels_behind",
                                               "unknown_frame"};
const std::set<std::string> kSegmentationRejections{"unknown_frame", "size_mismatch", "invalid_segmentation",
                                                    "label_out_of_legend", "unknown_camera"};

// Deltas of the counters whose reason is in `reasons`, for one camera ("" = every camera).
std::map<std::string, int64_t> deltas(const std::vector<client::ReasonCount>& before,
                                      const std::vector<client::ReasonCount>& after,
                                      const std::set<std::string>& reasons, const std::string& camera) {
  std::map<std::string, int64_t> out;
  auto add = [&](const std::vector<client::ReasonCount>& counts, int64_t sign) {
    for (const auto& c : counts)
      if (reasons.count(c.reason) && (camera.empty() || c.camera_id == camera))
        out[c.reason] += sign * static_cast<int64_t>(c.count);
  };
  add(after, 1);
  add(before, -1);
  for (auto it = out.begin(); it != out.end();) it = it->second == 0 ? out.erase(it) : std::next(it);
  return out;
}

const client::CameraStatus* findCamera(const client::ServerStatus& status, const std::string& id) {
  for (const auto& camera : status.cameras)
    if (camera.camera_id == id) return &camera;
  return nullptr;
}

int64_t sum(const std::map<std::string, int64_t>& counts) {
  int64_t total = 0;
  for (const auto& [reason, n] : counts) total += n;
  return total;
}

}  // namespace

int64_t InputAccount::unaccounted() const {
  // A frame map_replaced was posed and is counted among the drops as well.
  const int64_t replaced = dropped.count("map_replaced") ? dropped.at("map_replaced") : 0;
  const int64_t used = frames ? posed - replaced : integrated;
  return sent - used - held - head_loss - sum(dropped) - sum(rejected);
}

std::vector<InputAccount> accountInputs(const LoadResult& result) {
  std::vector<InputAccount> rows;
  for (const CameraRun& camera : result.cameras) {
    InputAccount row;
    row.what = camera.camera_id + (camera.posed ? " (posed)" : " (tracked)");
    row.sent = static_cast<int64_t>(camera.sent.sent + camera.sent.write_failures);
    const client::CameraStatus* before = findCamera(result.before, camera.camera_id);
    const client::CameraStatus* after = findCamera(result.after, camera.camera_id);
    if (after) {
      row.received = static_cast<int64_t>(after->frames_received - (before ? before->frames_received : 0));
      row.posed = static_cast<int64_t>(after->frames_posed - (before ? before->frames_posed : 0));
      row.integrated = static_cast<int64_t>(after->frames_integrated - (before ? before->frames_integrated : 0));
      row.skipped = static_cast<int64_t>(after->frames_skipped - (before ? before->frames_skipped : 0));
    }
    row.dropped = deltas(result.before.dropped, result.after.dropped, kFrameDrops, camera.camera_id);
    row.rejected = deltas(result.before.rejected, result.after.rejected, kFrameRejections, camera.camera_id);
    // The bench numbers a camera's frames from 0 (each slot, written or not), so the server's
    // first received sequence number is last_seq + 1 - received - gaps. A camera the status does
    // not list lost everything before a first frame: that stays unaccounted.
    if (after && !before && after->frames_received > 0) {
      const auto gaps = row.dropped.count("sequence_gap") ? row.dropped.at("sequence_gap") : 0;
      row.head_loss = std::max<int64_t>(0, static_cast<int64_t>(after->last_seq) + 1 - row.received - gaps);
    }
    rows.push_back(std::move(row));
  }
  // Frames still queued at the end belong to no camera in the status: the drain waits them out.
  if (!rows.empty()) rows.front().held += result.after.queued_frames;

  InputAccount segmentations;
  segmentations.what = "segmentations";
  segmentations.frames = false;
  for (const auto& s : result.segmenters) segmentations.sent += static_cast<int64_t>(s.published);
  segmentations.received =
      static_cast<int64_t>(result.after.segmentations_received - result.before.segmentations_received);
  segmentations.integrated =
      static_cast<int64_t>(result.after.segmentations_integrated - result.before.segmentations_integrated);
  segmentations.held = result.after.pending_segmentations;
  segmentations.dropped = deltas(result.before.dropped, result.after.dropped, kSegmentationDrops, "");
  segmentations.rejected = deltas(result.before.rejected, result.after.rejected, kSegmentationRejections, "");
  rows.push_back(std::move(segmentations));
  return rows;
}

std::string reasonsText(const std::map<std::string, int64_t>& counts) {
  std::string text;
  for (const auto& [reason, n] : counts) text += (text.empty() ? "" : ", ") + reason + " " + std::to_string(n);
  return text.empty() ? "0" : text;
}

int64_t droppedTotal(const LoadResult& result, const std::string& reason) {
  const auto counts = deltas(result.before.dropped, result.after.dropped, {reason}, "");
  const auto it = counts.find(reason);
  return it == counts.end() ? 0 : it->second;
}

}  // namespace semfuse::bench::load
