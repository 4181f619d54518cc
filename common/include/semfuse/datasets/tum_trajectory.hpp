#pragma once
// Trajectories in the TUM RGB-D format (Sturm et al., IROS 2012): one "timestamp tx ty tz qx qy qz
// qw" line per pose, camera-to-world, '#' comments. The benchmark's ground truth is written so,
// and so is what `semfuse-query poses` records, so an estimate can be compared with a motion
// capture trajectory by time.
#include <filesystem>
#include <optional>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::datasets {

struct TimedPose {
  double time = 0.0;  // seconds
  Pose pose = Pose::Identity();
};

// The poses of a trajectory file, sorted by time. Fails on a malformed line (naming file and
// line), a quaternion whose norm is not 1 (within 1e-3), or a missing file.
Result<std::vector<TimedPose>> readTumTrajectory(const std::filesystem::path& file);

// The pose at `time` from a time-sorted trajectory: interpolated between the samples on either
// side when both are within `window` seconds (translation linearly, rotation by slerp: motion
// capture runs at ~100 Hz against a camera's 30 Hz, so the nearest sample would be up to 5 ms
// off), else the nearest sample within the window, else none.
std::optional<Pose> trajectoryPoseAt(const std::vector<TimedPose>& sorted, double time, double window);

}  // namespace semfuse::datasets
