#pragma once
// Hard cases for tracking, made from a recorded sequence: the order in which its frames are
// played, and what is done to some of them.
//   full             every frame in order
//   stride:K         every K-th frame (faster motion: K times the motion per frame)
//   jump:A-B,C-D,..  frames A..B, then C..D, ... (a dropped link or a kidnapped camera)
//   covered:S+N      frames S..S+N-1 arrive with no depth and a black image (a covered sensor)
//   plane:S+N        frames S..S+N-1 keep only the depth of their dominant plane (a view of a
//                    wall or a floor: the depth constrains three of the six degrees of freedom)
#include <cstddef>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::bench {

enum class FrameAlteration { kNone, kCovered, kOnePlane };

struct PlaybackStep {
  std::size_t index = 0;  // frame of the sequence
  FrameAlteration alteration = FrameAlteration::kNone;
};

struct TrackCase {
  std::string spec;
  std::vector<PlaybackStep> steps;
  // Steps where the camera comes back after a break (the first step of each later segment of a
  // jump, the first uncovered frame): relocalisation is timed from each.
  std::vector<std::size_t> resumptions;
};

Result<TrackCase> makeTrackCase(const std::string& spec, std::size_t sequence_size);

// The frame as the case plays it (a shallow copy when nothing is altered).
Frame alterFrame(const Frame& frame, FrameAlteration alteration);

}  // namespace semfuse::bench
