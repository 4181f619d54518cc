#pragma once
// One tracking case played through the server's tracker and integrator, in process: each frame
// is tracked without its pose, integrated where the tracker says so, and recorded.
#include <cstddef>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/tracking/tracker.hpp"
#include "semfuse/volume/volume_params.hpp"
#include "track_cases.hpp"
#include "track_sequence.hpp"

namespace semfuse::bench {

struct FrameRecord {
  std::size_t index = 0;  // frame of the sequence
  tracking::TrackedFrame tracked;
  double track_ms = 0.0;      // wall clock of the tracker's call
  double track_cpu_ms = 0.0;  // process CPU time of the same call (all threads)
  double integrate_ms = 0.0;
  bool integrated() const { return tracked.shouldIntegrate(); }
};

struct CaseRun {
  std::vector<FrameRecord> frames;  // one per step of the case
};

struct RunOptions {
  volume::VolumeParams volume;
  tracking::TrackerConfig tracker;
  bool verbose = false;
  double depth_scale = 1.0;  // diagnostic: every depth reading multiplied by this  // one line per frame (lost and
                             // relocalised frames are always printed)
};

Result<CaseRun> runCase(const TrackSequence& sequence, const TrackCase& track_case, const RunOptions& options);

}  // namespace semfuse::bench
