#pragma once
// What the server's threads share besides the map: counters, errors, per-camera activity.
// Everything here is safe to touch from any thread.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "event_counters.hpp"
#include "stage_timings.hpp"

namespace semfuse::server {

// Reasons under which inputs are dropped (accepted, then given up for capacity or time) or
// rejected (malformed or inconsistent). They appear verbatim in ServerStatus.
namespace reason {
inline constexpr const char* kQueueFull = "queue_full";  // drop: newer frame came
// Drop: the camera's oldest queued frame waited longer than --max-queue-wait, and tracking took
// the camera's newest instead of the frames before it.
inline constexpr const char* kQueueStale = "queue_stale";
// Frames the ingest never saw, from gaps in a camera's sequence numbers: lost on the network or
// overwritten in the DDS reader's history (or skipped on purpose by the camera, e.g. a stride).
inline constexpr const char* kSequenceGap = "sequence_gap";
inline constexpr const char* kPendingFull = "pending_full";                  // drop: too many waiting
inline constexpr const char* kSegmentationTimeout = "segmentation_timeout";  // drop: frame never came
// A waiting segmentation whose frame will not come: a later frame of its camera was fused first,
// so its own was dropped before fusion (queue_full, queue_stale) or never received (sequence_gap).
inline constexpr const char* kFrameDropped = "frame_dropped";
// A segmentation whose label pass was passed over: more of them queued than the fusion thread
// runs beside its integrations (frames newest first only).
inline constexpr const char* kLabelsBehind = "labels_behind";
inline constexpr const char* kTrackingLost = "tracking_lost";  // frame not integrated
// A posed frame tracked against a map that a load or reset then replaced: not integrated.
inline constexpr const char* kMapReplaced = "map_replaced";
inline constexpr const char* kInvalidFrame = "invalid_frame";
inline constexpr const char* kInvalidSegmentation = "invalid_segmentation";
inline constexpr const char* kLabelOutOfLegend = "label_out_of_legend";
inline constexpr const char* kUnknownCamera = "unknown_camera";
inline constexpr const char* kUnknownFrame = "unknown_frame";  // evicted, lost, or never seen
inline constexpr const char* kSizeMismatch = "size_mismatch";  // segmentation larger than frame
inline constexpr const char* kIntegrationFailed = "integration_failed";
inline constexpr const char* kInvalidQuery = "invalid_query";  // a query the server refused
}  // namespace reason

// What tracking made of one frame of a camera.
struct TrackResult {
  bool posed = false;
  uint8_t tracking_state = 0;  // TrackedPose_Constants
  std::string lost_reason;     // why tracking is lost; empty while tracking
  uint64_t frames_since_lost = 0;
  uint64_t relocalisations = 0;
};

struct CameraActivity {
  uint8_t tracking_state = 0;  // TrackedPose_Constants
  std::string lost_reason;
  uint64_t frames_since_lost = 0;
  uint64_t relocalisations = 0;
  uint64_t last_seq = 0;
  uint64_t frames_received = 0;
  uint64_t frames_posed = 0;       // tracked (or given) a pose
  uint64_t frames_integrated = 0;  // of those, fused into the map
  uint64_t frames_skipped = 0;     // of those, passed over by integration for a newer one
  uint64_t frames_lost = 0;        // tracking lost: no pose
  std::chrono::steady_clock::time_point last_frame_time{};
  double rate_hz = 0.0;  // exponential moving average of the arrival rate
};

class ServerState {
 public:
  using Clock = std::chrono::steady_clock;

  EventCounters dropped;
  EventCounters rejected;
  ErrorLog errors{16};
  StageTimings stages;

  std::atomic<uint64_t> frames_received{0};
  std::atomic<uint64_t> frames_posed{0};
  std::atomic<uint64_t> frames_integrated{0};
  std::atomic<uint64_t> frames_skipped{0};
  std::atomic<uint64_t> frames_lost{0};
  std::atomic<uint64_t> segmentations_received{0};
  std::atomic<uint64_t> segmentations_integrated{0};

  // Records a rejection: counter + error log + one warning line.
  void reject(const char* why, const std::string& camera_id, const std::string& source, const std::string& message);

  void frameArrived(const std::string& camera_id, uint64_t seq, Clock::time_point now = Clock::now());
  void frameTracked(const std::string& camera_id, const TrackResult& result);
  // A posed frame integrated, or skipped for a newer one of its camera.
  void frameIntegrated(const std::string& camera_id);
  void frameSkipped(const std::string& camera_id);
  std::map<std::string, CameraActivity> cameras() const;
  bool knowsCamera(const std::string& camera_id) const;
  // Changes whenever a counter the status reports changes (for "publish on change").
  uint64_t changeCount() const { return changes_.load(); }
  void touch() { ++changes_; }

 private:
  mutable std::mutex mutex_;
  std::map<std::string, CameraActivity> cameras_;
  std::atomic<uint64_t> changes_{0};
};

}  // namespace semfuse::server
