#include "track/track_run.hpp"

#include <cstdio>

#include "semfuse/tracking/se3.hpp"
#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::bench {

namespace {

// The alignment's quality tests at a given pose, without moving it.
tracking::TrackerParams probeParams(const tracking::TrackerParams& params) {
  tracking::TrackerParams probe = params;
  probe.max_iterations.fill(0);
  return probe;
}

}  // namespace

Result<CaseRun> runCase(const TrackSequence& sequence, const TrackCase& track_case, const RunOptions& options,
                        const std::vector<std::optional<Pose>>& judge) {
  CaseRun run;
  tracking::SdfTracker probe(probeParams(options.tracker.alignment));
  volume::LabeledVolume map(options.volume);
  const tracking::VolumeField field(map);
  tracking::TrackerConfig config = options.tracker;
  // The trajectory is reported in the reference's frame: the first frame is placed at its
  // reference pose, the only reference pose the tracker ever sees.
  const std::optional<Pose>& first = sequence.reference(track_case.steps.front().index);
  if (!first) return makeError("the case's first frame has no reference pose to start from");
  config.initial_pose = *first;
  tracking::Tracker tracker(config);
  for (std::size_t step = 0; step < track_case.steps.size(); ++step) {
    const PlaybackStep& play = track_case.steps[step];
    Frame frame = alterFrame(sequence.frame(play.index), play.alteration);
    if (options.depth_scale != 1.0) frame.depth = frame.depth * options.depth_scale;
    FrameRecord record;
    record.index = play.index;
    Stopwatch watch;
    CpuStopwatch cpu;
    Result<tracking::TrackedFrame> tracked = tracker.track(frame, field, map.framesIntegrated() == 0);
    record.track_ms = watch.elapsedMs();
    record.track_cpu_ms = cpu.elapsedMs();
    if (!tracked) return makeError("frame " + std::to_string(play.index) + ": " + tracked.error());
    record.tracked = tracked.value();
    if (record.integrated()) {
      Stopwatch integrate_watch;
      Frame posed = frame;
      posed.camera_to_world = record.tracked.pose;
      auto stats = volume::integrate(map, posed, nullptr);
      record.integrate_ms = integrate_watch.elapsedMs();
      if (!stats) return makeError("integrate frame " + std::to_string(play.index) + ": " + stats.error());
      tracker.integrated(frame, record.tracked);
    } else if (play.index < judge.size() && judge[play.index] && map.framesIntegrated() > 0) {
      auto at_truth = probe.align(frame.depth, frame.intrinsics, field, *judge[play.index]);
      record.sees_map = at_truth && at_truth.value().quality.inlier_ratio >= 0.5;
    }
    const auto& t = record.tracked;
    const bool notable =
        t.status == tracking::TrackingStatus::kLost || t.status == tracking::TrackingStatus::kRelocalised;
    if (options.verbose || notable) {
      const Pose reference = sequence.reference(play.index).value_or(t.pose);
      const Pose correction = t.guess.inverse() * t.pose;
      std::printf(
          "  frame %4zu %-12s %-22s inliers %.2f agree %.2f rms %.2f mm rcond %.1e dofs %d images %.2f "
          "start %2d correction %5.1f mm %4.2f deg  iters %3d %5.1f ms  vs reference %5.1f mm%s\n",
          play.index, tracking::toString(t.status), tracking::toString(t.lost_reason), t.quality.inlier_ratio,
          t.quality.observed_agreement, t.quality.rms_residual_m * 1e3, t.quality.hessian_rcond,
          t.quality.constrained_dofs, t.image_matched, t.quality.start, correction.translation().norm() * 1e3,
          tracking::rotationAngle(correction.linear()) * 180.0 / M_PI, t.quality.iterations, record.track_ms,
          (t.pose.translation() - reference.translation()).norm() * 1e3,
          record.sees_map ? "  (shows mapped space)" : "");
    }
    run.frames.push_back(std::move(record));
  }
  return run;
}

}  // namespace semfuse::bench
