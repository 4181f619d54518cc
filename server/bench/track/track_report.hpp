#pragma once
// What a tracking case achieved, in the terms of the TUM RGB-D benchmark (Sturm et al., IROS
// 2012): absolute trajectory error after the best rigid alignment (ATE), per-frame relative pose
// error (RPE), plus what the hard cases are about: frames lost, relocalisations, how many frames
// a comeback took, and whether any frame was integrated at a wrong pose.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "semfuse/core/types.hpp"
#include "track/track_cases.hpp"
#include "track/track_run.hpp"

namespace semfuse::bench {

// An integrated pose farther than this from its reference (after the rigid alignment) was wrong.
inline constexpr double kWrongPoseMetres = 0.05;
inline constexpr double kWrongPoseDegrees = 3.0;

struct CaseSummary {
  std::string spec;
  std::size_t played = 0;
  std::size_t integrated = 0;
  std::size_t lost = 0;
  std::size_t lost_altered = 0;  // of the lost: frames the case altered (no depth, one plane)
  std::size_t relocalisations = 0;
  std::size_t lost_seeing_map = 0;  // of the lost: frames that showed mapped space at their judging pose
  // Frames from each comeback (the first frame after a break that shows mapped space) to the
  // first integrated frame; the largest. Empty when no break was followed by mapped space.
  std::optional<std::size_t> max_frames_to_resume;
  bool resumed_every_time = true;
  double ate_rmse_m = 0.0;  // integrated frames against the judging reference, aligned
  // Against the sequence's own reference when it is not the judge (7-Scenes' KinectFusion poses).
  std::optional<double> ate_sequence_reference_m;
  double ate_max_m = 0.0;
  double rotation_max_deg = 0.0;     // largest rotation error after the same alignment
  double rotation_median_deg = 0.0;  // and its median
  std::size_t wrong_poses = 0;       // integrated frames beyond kWrongPose* from the judging reference
  double rpe_translation_rmse_m = 0.0;
  double rpe_rotation_rmse_deg = 0.0;
  Timings track_ms, track_cpu_ms, integrate_ms;
};

// `judge`: per sequence frame, the pose an integrated frame is judged against (the reference for
// motion capture / exact poses, an unbroken run's pose otherwise); nullopt = not judged.
// `sequence_reference` (may be empty): the sequence's own poses, when they are not the judge.
CaseSummary summarise(const TrackCase& track_case, const CaseRun& run, const std::vector<std::optional<Pose>>& judge,
                      const std::vector<std::optional<Pose>>& sequence_reference = {});

// One row per case, aligned columns.
void printCaseTable(const std::string& title, const std::string& judged_against, const std::vector<CaseSummary>& rows);

}  // namespace semfuse::bench
