#include "track/track_consistency.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include "semfuse/tracking/sdf_tracker.hpp"
#include "semfuse/tracking/se3.hpp"
#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::bench {
namespace {

constexpr std::size_t kHalfWindow = 20;
constexpr std::size_t kStep = 5;

struct Consistency {
  double translation_rms_m = 0.0;
  double rotation_rms_deg = 0.0;
  double residual_mean_m = 0.0;
  std::size_t samples = 0;
};

// poses[i]: the trajectory's pose of sequence frame i, or none (frame not integrated).
Result<Consistency> localConsistency(const TrackSequence& sequence, const std::vector<std::optional<Pose>>& poses,
                                     const RunOptions& options) {
  Consistency out;
  tracking::SdfTracker aligner(options.tracker.alignment);
  double t_sq = 0.0, r_sq = 0.0, residual = 0.0;
  for (std::size_t i = kHalfWindow; i + kHalfWindow < poses.size(); i += kStep) {
    if (!poses[i]) continue;
    volume::LabeledVolume map(options.volume);
    for (std::size_t j = i - kHalfWindow; j <= i + kHalfWindow; ++j) {
      if (j == i || !poses[j]) continue;
      Frame posed = sequence.frame(j);
      posed.camera_to_world = *poses[j];
      auto stats = volume::integrate(map, posed, nullptr);
      if (!stats) return makeError(stats.error());
    }
    const Frame& frame = sequence.frame(i);
    auto aligned = aligner.align(frame.depth, frame.intrinsics, tracking::VolumeField(map), *poses[i]);
    if (!aligned) return makeError(aligned.error());
    const Pose pull = poses[i]->inverse() * aligned.value().pose;
    const double angle = tracking::rotationAngle(pull.linear()) * 180.0 / M_PI;
    t_sq += pull.translation().squaredNorm();
    r_sq += angle * angle;
    residual += aligned.value().quality.rms_residual_m;
    ++out.samples;
  }
  if (out.samples == 0) return makeError("too few frames for the consistency check");
  const auto n = static_cast<double>(out.samples);
  out.translation_rms_m = std::sqrt(t_sq / n);
  out.rotation_rms_deg = std::sqrt(r_sq / n);
  out.residual_mean_m = residual / n;
  return out;
}

}  // namespace

int reportConsistency(const TrackSequence& sequence, const CaseRun& run, const RunOptions& options) {
  std::vector<std::optional<Pose>> tracked(sequence.size()), reference(sequence.size());
  for (const FrameRecord& record : run.frames)
    if (record.integrated()) tracked[record.index] = record.tracked.pose;
  for (std::size_t i = 0; i < sequence.size(); ++i) reference[i] = sequence.reference(i);
  Table table("local consistency with the depth: every " + std::to_string(kStep) + "th frame aligned to its " +
              std::to_string(2 * kHalfWindow) + " neighbours fused at the same trajectory");
  for (const auto& [name, poses] :
       {std::pair<std::string, const std::vector<std::optional<Pose>>*>{"tracked poses", &tracked},
        {"reference poses", &reference}}) {
    auto result = localConsistency(sequence, *poses, options);
    if (!result) {
      std::fprintf(stderr, "consistency: %s\n", result.error().c_str());
      return 1;
    }
    const Consistency& c = result.value();
    table.add(
        name + ": pull RMS",
        formatNumber(c.translation_rms_m * 1000, 2) + " mm, " + formatNumber(c.rotation_rms_deg, 3) + " deg",
        "residual " + formatNumber(c.residual_mean_m * 1000, 2) + " mm; " + std::to_string(c.samples) + " frames");
  }
  table.print();
  return 0;
}

}  // namespace semfuse::bench
