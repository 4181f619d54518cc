#pragma once
// What the fusion loop keeps for segmentations that come late or early: the frame history and the
// segmentations waiting for their frame. The server's --history-frames, --history-megabytes,
// --pending-segmentations and --pending-timeout set these; the defaults are here only.
#include <cstddef>

namespace semfuse::server {

struct FusionLimits {
  size_t history_frames = 120;        // frames kept for late segmentations
  size_t history_megabytes = 512;     // memory bound of that history
  size_t pending_segmentations = 64;  // segmentations that may wait for their frame
  double pending_timeout_s = 10.0;    // how long one waits, seconds
};

}  // namespace semfuse::server
