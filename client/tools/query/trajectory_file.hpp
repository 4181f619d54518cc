#pragma once
// Lines of a trajectory file from the server's poses, in the formats trajectory tools read: TUM
// ("timestamp tx ty tz qx qy qz qw", what the TUM RGB-D benchmark's evaluate_ate.py and evo
// take), KITTI (the 3x4 camera-to-world matrix, row-major, one line per pose) and CSV (every
// field of a pose, with a header).
#include <optional>
#include <string>

#include "semfuse/core/types.hpp"

namespace semfuse::tools {

enum class TrajectoryFormat { kTum, kKitti, kCsv };

// "tum", "kitti" or "csv".
std::optional<TrajectoryFormat> trajectoryFormatNamed(const std::string& name);

// The file's first lines (a comment for TUM, the column names for CSV, nothing for KITTI).
std::string trajectoryHeader(TrajectoryFormat format);

// One pose as one line, with its newline.
std::string trajectoryLine(const TrackedPose& pose, TrajectoryFormat format);

}  // namespace semfuse::tools
