#pragma once
// How the frame pipeline runs and what the fusion loop keeps for segmentations that come late or
// early: the tracking threads, whether integration may skip frames, the frame history and the
// segmentations waiting for their frame. The server's --tracking-threads, --max-queue-wait 0,
// --history-frames, --history-megabytes, --pending-segmentations and --pending-timeout set these;
// the defaults are here only.
#include <cstddef>

namespace semfuse::server {

struct FusionLimits {
  size_t tracking_threads = 0;         // 0 = one per core, at most 4
  bool integrate_every_frame = false;  // false: the newest posed frame of a camera, the rest skipped
  size_t history_frames = 120;         // frames kept for late segmentations
  size_t history_megabytes = 512;      // memory bound of that history
  size_t pending_segmentations = 64;   // segmentations that may wait for their frame
  double pending_timeout_s = 10.0;     // how long one waits, seconds
};

}  // namespace semfuse::server
