#pragma once
// ServerStatus: a snapshot of what the server has done and holds, and its wire form. Published
// on rt/semfuse/status and returned by the admin service.
#include <cstdint>
#include <string>
#include <vector>

#include "event_counters.hpp"
#include "server_state.hpp"
#include "msg.h"

namespace semfuse::server {

struct StatusSnapshot {
  std::string server_id;
  double uptime_s = 0.0;
  uint64_t frames_received = 0;
  uint64_t frames_integrated = 0;
  uint64_t frames_lost = 0;
  uint64_t segmentations_received = 0;
  uint64_t segmentations_integrated = 0;
  std::vector<CounterEntry> dropped;
  std::vector<CounterEntry> rejected;
  uint32_t queued_frames = 0;
  uint32_t pending_segmentations = 0;
  uint32_t history_frames = 0;
  double voxel_size = 0.0;
  double truncation = 0.0;
  uint64_t allocated_voxels = 0;
  uint64_t allocated_blocks = 0;
  uint64_t map_bytes = 0;
  uint64_t rss_bytes = 0;
  struct Camera {
    std::string id;
    CameraActivity activity;
    float last_frame_age_s = 0.0f;
    bool stale = false;
  };
  std::vector<Camera> cameras;
  std::vector<ErrorRecord> last_errors;
  std::string map_file;
  bool last_save_ok = true;
  double last_save_age_s = -1.0;  // negative: never saved
};

// Fills `out` (whose strings and sequences are freed first by the caller, e.g. Sample::clear)
// with dds_alloc'd copies, so it can be written or freed with dds_sample_free.
void fillStatusMessage(const StatusSnapshot& snapshot, semfuse_msg_dds__ServerStatus_& out);

// Resident set size of this process, bytes (0 where /proc is not readable).
uint64_t currentRssBytes();

}  // namespace semfuse::server
