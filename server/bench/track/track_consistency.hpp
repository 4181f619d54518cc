#pragma once
// How well a trajectory agrees with the depth locally, independent of drift: every 5th frame is
// aligned, from its own pose, to a map of its 40 neighbours fused at their poses of the same
// trajectory. A trajectory the depth supports moves little. Used to tell tracker error from
// reference error where the reference is itself a reconstruction (7-Scenes).
#include "track/track_run.hpp"
#include "track/track_sequence.hpp"

namespace semfuse::bench {

// Prints the pull of the tracked (integrated frames of `run`) and the reference trajectory.
int reportConsistency(const TrackSequence& sequence, const CaseRun& run, const RunOptions& options);

}  // namespace semfuse::bench
