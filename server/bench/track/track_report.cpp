#include "track/track_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "semfuse/tracking/se3.hpp"
#include "semfuse/tracking/trajectory_metrics.hpp"

namespace semfuse::bench {
namespace {

bool altered(const TrackCase& track_case, std::size_t step) {
  return track_case.steps[step].alteration != FrameAlteration::kNone;
}

std::string cm(double metres) { return formatNumber(metres * 100.0, 2); }

// The rigid transform that best fits whole poses of `estimate` onto `reference`: Umeyama over each
// camera's centre and three points half a metre along its axes. The TUM convention (centres
// only) fits positions best, but on a short trajectory its rotation is poorly determined (1 cm of
// position error over 15 cm of motion tilts it by degrees), which would make every orientation
// look wrong by a constant; poses are judged after this fit instead.
Pose poseAlignment(const std::vector<Pose>& estimate, const std::vector<Pose>& reference) {
  constexpr double kArm = 0.5;
  const auto n = static_cast<Eigen::Index>(estimate.size());
  Eigen::Matrix3Xd from(3, 4 * n), to(3, 4 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d arm =
          a == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(kArm * Eigen::Vector3d::Unit(a - 1));
      from.col(4 * i + a) = estimate[k] * arm;
      to.col(4 * i + a) = reference[k] * arm;
    }
  }
  return Pose(Eigen::umeyama(from, to, /*with_scaling=*/false));
}

}  // namespace

CaseSummary summarise(const TrackCase& track_case, const CaseRun& run, const std::vector<std::optional<Pose>>& judge,
                      const std::vector<std::optional<Pose>>& sequence_reference) {
  CaseSummary out;
  out.spec = track_case.spec;
  out.played = run.frames.size();
  std::vector<Pose> estimate, reference;
  for (std::size_t step = 0; step < run.frames.size(); ++step) {
    const FrameRecord& record = run.frames[step];
    if (step > 0) {
      out.track_ms.add(record.track_ms);
      out.track_cpu_ms.add(record.track_cpu_ms);
    }
    if (record.tracked.status == tracking::TrackingStatus::kRelocalised) ++out.relocalisations;
    if (!record.integrated()) {
      ++out.lost;
      if (altered(track_case, step)) ++out.lost_altered;
      continue;
    }
    ++out.integrated;
    out.integrate_ms.add(record.integrate_ms);
    if (record.index < judge.size() && judge[record.index]) {
      estimate.push_back(record.tracked.pose);
      reference.push_back(*judge[record.index]);
    }
  }
  // A comeback counts from the first frame after the break that shows mapped space: a camera
  // cannot be found again before it sees something the map holds.
  for (std::size_t resume : track_case.resumptions) {
    std::size_t seen = resume;
    while (seen < run.frames.size() && !run.frames[seen].integrated() && !run.frames[seen].sees_map) ++seen;
    if (seen == run.frames.size()) continue;  // never saw mapped space again
    std::size_t step = seen;
    while (step < run.frames.size() && !run.frames[step].integrated()) ++step;
    if (step == run.frames.size()) {
      out.resumed_every_time = false;
      continue;
    }
    out.max_frames_to_resume = std::max(out.max_frames_to_resume.value_or(0), step - seen);
  }
  for (const FrameRecord& record : run.frames)
    if (!record.integrated() && record.sees_map) ++out.lost_seeing_map;
  if (!sequence_reference.empty()) {
    std::vector<Pose> tracked, own;
    for (const FrameRecord& record : run.frames) {
      if (!record.integrated() || record.index >= sequence_reference.size() || !sequence_reference[record.index])
        continue;
      tracked.push_back(record.tracked.pose);
      own.push_back(*sequence_reference[record.index]);
    }
    if (auto own_ate = tracking::absoluteTrajectoryError(tracked, own, /*align=*/true))
      out.ate_sequence_reference_m = own_ate.value().rmse_m;
  }
  auto ate = tracking::absoluteTrajectoryError(estimate, reference, /*align=*/true);
  if (ate) {
    out.ate_rmse_m = ate.value().rmse_m;
    out.ate_max_m = ate.value().max_m;
    const Pose alignment = poseAlignment(estimate, reference);
    std::vector<double> rotations;
    for (std::size_t i = 0; i < estimate.size(); ++i) {
      const Pose aligned = alignment * estimate[i];
      const double t = (aligned.translation() - reference[i].translation()).norm();
      const double r = tracking::rotationAngle(aligned.linear().transpose() * reference[i].linear()) * 180.0 / M_PI;
      out.rotation_max_deg = std::max(out.rotation_max_deg, r);
      rotations.push_back(r);
      if (t > kWrongPoseMetres || r > kWrongPoseDegrees) ++out.wrong_poses;
    }
    std::nth_element(rotations.begin(), rotations.begin() + static_cast<std::ptrdiff_t>(rotations.size() / 2),
                     rotations.end());
    out.rotation_median_deg = rotations[rotations.size() / 2];
  }
  // RPE over consecutive steps that were both integrated and judged.
  double t_sq = 0.0, r_sq = 0.0;
  std::size_t pairs = 0;
  for (std::size_t step = 1; step < run.frames.size(); ++step) {
    const FrameRecord& a = run.frames[step - 1];
    const FrameRecord& b = run.frames[step];
    if (!a.integrated() || !b.integrated() || a.index >= judge.size() || b.index >= judge.size() || !judge[a.index] ||
        !judge[b.index])
      continue;
    const Pose ref_motion = judge[a.index]->inverse() * *judge[b.index];
    const Pose est_motion = a.tracked.pose.inverse() * b.tracked.pose;
    const Pose error = ref_motion.inverse() * est_motion;
    t_sq += error.translation().squaredNorm();
    const double r = tracking::rotationAngle(error.linear()) * 180.0 / M_PI;
    r_sq += r * r;
    ++pairs;
  }
  if (pairs > 0) {
    out.rpe_translation_rmse_m = std::sqrt(t_sq / static_cast<double>(pairs));
    out.rpe_rotation_rmse_deg = std::sqrt(r_sq / static_cast<double>(pairs));
  }
  return out;
}

void printCaseTable(const std::string& title, const std::string& judged_against, const std::vector<CaseSummary>& rows) {
  std::vector<std::vector<std::string>> cells;
  const bool own_reference = std::any_of(rows.begin(), rows.end(),
                                         [](const CaseSummary& s) { return s.ate_sequence_reference_m.has_value(); });
  cells.push_back({"case", "frames", "integrated", "lost", "reloc", "comeback", "ATE cm", "max cm", "deg p50/max",
                   "wrong", "RPE mm", "RPE deg", "track ms p50/p95", "CPU ms p50"});
  if (own_reference) cells.back().push_back("ATE vs dataset cm");
  for (const CaseSummary& s : rows) {
    std::string comeback = "-";
    if (s.max_frames_to_resume) comeback = std::to_string(*s.max_frames_to_resume);
    if (!s.resumed_every_time) comeback = "never";
    std::string lost = std::to_string(s.lost);
    if (s.lost > 0) {
      lost += " (" + std::to_string(s.lost_seeing_map) + " saw map";
      if (s.lost_altered > 0) lost += ", " + std::to_string(s.lost_altered) + " altered";
      lost += ")";
    }
    cells.push_back({s.spec, std::to_string(s.played), std::to_string(s.integrated), lost,
                     std::to_string(s.relocalisations), comeback, cm(s.ate_rmse_m), cm(s.ate_max_m),
                     formatNumber(s.rotation_median_deg, 2) + " / " + formatNumber(s.rotation_max_deg, 2),
                     std::to_string(s.wrong_poses), formatNumber(s.rpe_translation_rmse_m * 1000.0, 2),
                     formatNumber(s.rpe_rotation_rmse_deg, 3),
                     formatNumber(s.track_ms.median(), 1) + " / " + formatNumber(s.track_ms.p95(), 1),
                     formatNumber(s.track_cpu_ms.median(), 1)});
    if (own_reference) cells.back().push_back(s.ate_sequence_reference_m ? cm(*s.ate_sequence_reference_m) : "-");
  }
  std::vector<std::size_t> widths(cells.front().size(), 0);
  for (const auto& row : cells)
    for (std::size_t c = 0; c < row.size(); ++c) widths[c] = std::max(widths[c], row[c].size());
  std::printf(
      "\n%s\n  ATE (camera centres, TUM convention) and pose errors of the integrated frames against %s;\n"
      "  deg p50/max: rotation errors and wrong: poses farther than %.0f cm or %.0f deg, after fitting whole\n"
      "  poses; lost (saw map): of the frames not integrated, those that showed mapped space at their\n"
      "  true pose (half their points on mapped surfaces); comeback: most frames from the first frame after\n"
      "  a jump or an uncovered sensor that shows mapped space to the next integrated frame%s\n",
      title.c_str(), judged_against.c_str(), kWrongPoseMetres * 100.0, kWrongPoseDegrees,
      own_reference ? ";\n  ATE vs dataset: the same frames against the dataset's own poses" : "");
  for (const auto& row : cells) {
    std::printf("  %-*s", static_cast<int>(widths[0]), row[0].c_str());
    for (std::size_t c = 1; c < row.size(); ++c) std::printf("  %*s", static_cast<int>(widths[c]), row[c].c_str());
    std::printf("\n");
  }
  std::fflush(stdout);
}

}  // namespace semfuse::bench
