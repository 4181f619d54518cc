#pragma once
// One tracking case played through the server's tracker and integrator, in process: each frame
// is tracked without its pose, integrated where the tracker says so, and recorded.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/tracking/tracker.hpp"
#include "semfuse/volume/volume_params.hpp"
#include "track/track_cases.hpp"
#include "track/track_sequence.hpp"

namespace semfuse::bench {

struct FrameRecord {
  std::size_t index = 0;  // frame of the sequence
  tracking::TrackedFrame tracked;
  double track_ms = 0.0;      // wall clock of the tracker's call
  double track_cpu_ms = 0.0;  // process CPU time of the same call (all threads)
  double integrate_ms = 0.0;
  // For a frame that was not integrated: whether, at its judging pose, at least half of its points
  // lie on the surfaces mapped so far (it shows mapped space, so relocalisation could find it).
  bool sees_map = false;
  bool integrated() const { return tracked.shouldIntegrate(); }
};

struct CaseRun {
  std::vector<FrameRecord> frames;  // one per step of the case
};

struct RunOptions {
  volume::VolumeParams volume;
  tracking::TrackerConfig tracker;
  bool verbose = false;      // one line per frame (lost and relocalised frames are always printed)
  double depth_scale = 1.0;  // diagnostic: every depth reading multiplied by this
};

// `judge` (per sequence frame, may be empty): the poses at which lost frames are checked for
// showing mapped space (FrameRecord::sees_map).
Result<CaseRun> runCase(const TrackSequence& sequence, const TrackCase& track_case, const RunOptions& options,
                        const std::vector<std::optional<Pose>>& judge = {});

}  // namespace semfuse::bench
