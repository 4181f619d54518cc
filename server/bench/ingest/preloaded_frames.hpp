#pragma once
// The frames the ingest bench's cameras replay, encoded once (depth raw 16UC1, png16 or rvl, colour
// JPEG) so that the publishers spend no CPU on codecs during the measurement: on a 2-core host
// every cycle the bench burns is taken from the server. Each camera thread sends a shallow copy
// of a message with its own camera_id, seq and stamp: the payload buffers are shared and only
// read by dds_write.
#include <string>
#include <vector>

#include "ingest_options.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/wire/frame_codec.hpp"

namespace semfuse::bench::ingest {

struct Preloaded {
  std::vector<wire::EncodedFrame> frames;
  std::vector<Pose> poses;
  PinholeIntrinsics intrinsics;
  double depth_kb = 0, color_kb = 0;  // mean payload per frame
};

// The first options.frames frames of the 7-Scenes sequence at options.data, which must carry poses.
Result<Preloaded> preload(const IngestOptions& options);

// The wire's depth encoding for --depth raw|png|rvl: "16UC1", "png16" or "rvl".
std::string depthWireEncoding(const std::string& option);

}  // namespace semfuse::bench::ingest
