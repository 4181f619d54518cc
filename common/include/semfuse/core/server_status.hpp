#pragma once
// The server's published state (topic rt/semfuse/status, also returned by the admin service), as
// plain C++ values: the server fills one per status message, clients decode into one.
#include <cstdint>
#include <string>
#include <vector>

namespace semfuse {

struct ReasonCount {
  std::string reason;
  std::string camera_id;  // empty when not camera specific
  uint64_t count = 0;
};

struct CameraStatus {
  std::string camera_id;
  uint8_t tracking_state = 0;  // PoseState: 0 given, 1 tracked, 2 refined, 3 lost
  uint64_t last_seq = 0;
  uint64_t frames_received = 0;
  uint64_t frames_posed = 0;       // given or tracked a pose
  uint64_t frames_integrated = 0;  // of those, fused into the map
  uint64_t frames_skipped = 0;     // of those, passed over by integration for a newer frame
  uint64_t frames_lost = 0;        // tracking lost: no pose
  float frame_rate_hz = 0.0F;
  float last_frame_age_s = 0.0F;
  bool stale = false;
  std::string lost_reason;  // why tracking is lost now; empty while tracking or with given poses
  uint64_t frames_since_lost = 0;
  uint64_t relocalisations = 0;  // times a keyframe found the camera again (or placed it)
};

struct ServerError {
  double stamp_s = 0.0;
  std::string source;
  std::string message;
};

// How long one stage of the server's work took over its most recent runs (stage_timings.hpp in
// server/core names the stages).
struct StageTiming {
  std::string stage;
  uint64_t count = 0;                                 // runs since the server started
  float p50_ms = 0.0F, p95_ms = 0.0F, max_ms = 0.0F;  // over the last (at most 1,000) runs
};

struct ServerStatus {
  std::string server_id;
  std::string version;
  double uptime_s = 0.0;
  uint64_t frames_received = 0;
  uint64_t frames_posed = 0;
  uint64_t frames_integrated = 0;
  uint64_t frames_skipped = 0;
  uint64_t frames_lost = 0;
  uint64_t segmentations_received = 0;
  uint64_t segmentations_integrated = 0;
  std::vector<ReasonCount> dropped;
  std::vector<ReasonCount> rejected;
  uint32_t queued_frames = 0;
  uint32_t pending_segmentations = 0;
  uint32_t history_frames = 0;
  double voxel_size = 0.0;
  double truncation = 0.0;
  uint64_t allocated_voxels = 0;
  uint64_t allocated_blocks = 0;
  uint64_t map_bytes = 0;
  uint64_t rss_bytes = 0;
  std::vector<CameraStatus> cameras;
  std::vector<ServerError> last_errors;
  std::string map_file;
  bool last_save_ok = false;
  double last_save_age_s = 0.0;          // negative: never saved
  std::vector<StageTiming> stages;       // the stages that ran at least once, in pipeline order
  uint64_t map_revision = 0;             // raised by every change to the map
  uint64_t distance_field_revision = 0;  // the map revision the distance field reflects; 0 without one
  uint64_t snapshot_bytes = 0;  // the map's copies kept for queries that run without its lock (region, objects, mesh)
};

// Name of a tracking state ("given", "tracked", "refined", "lost", "unknown").
const char* trackingStateName(uint8_t state);

}  // namespace semfuse
