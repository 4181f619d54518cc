// semfuse-bench track: camera tracking by SDF alignment (issue 4's evaluation).
//  - 7-Scenes redkitchen: the first frame is placed at its reference pose, every later frame is
//    tracked from depth alone against the map built from the tracked poses, and the trajectory is
//    compared with the reference (KinectFusion) poses.
//  - Synthetic room: the same loop on exact rendered depth, where the true poses are known.
// Frames are decoded / rendered outside the timed region; "tracking" is one trackFrame() call
// (pyramid, alignment, quality checks), "integration" one integrate() call.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/core/malloc_tuning.hpp"
#include "semfuse/datasets/seven_scenes.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/tracking/camera_tracking.hpp"
#include "semfuse/tracking/se3.hpp"
#include "semfuse/tracking/trajectory_metrics.hpp"
#include "semfuse/tracking/volume_field.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::bench {
namespace {

struct TrackBenchOptions {
  std::string data = redkitchenDir().string();
  std::size_t frames = 500;
  double voxel = 0.01;
  double truncation = 0.05;
  int synthetic_frames = 300;
  bool skip_seven_scenes = false;
  bool skip_synthetic = false;
  bool verbose = false;
  // Diagnostic: build the map at the reference poses instead of the tracked ones, so that the
  // trajectory error measures how far depth alignment and reference disagree frame by frame,
  // without accumulated drift.
  bool oracle_map = false;
  // Diagnostic: start every alignment at the frame's reference pose (refinement) instead of the
  // motion prediction; with --oracle-map this measures how far the depth pulls each reference pose.
  bool oracle_guess = false;
  // Diagnostic: multiply every depth reading (tests a depth scale error of the sensor).
  double depth_scale = 1.0;
  // Diagnostic: focal length (fx = fy, pixels) instead of the dataset's camera-intrinsics.txt.
  double focal = 0.0;
  // Diagnostic: pair depth frame i with the reference pose of frame i + pose_offset (tests whether
  // depth and reference poses are synchronised).
  int pose_offset = 0;
  // Diagnostic: how well each trajectory (tracked and reference) agrees with the depth locally.
  bool consistency = false;
  // Per-frame CSV (status, errors against the reference, quality) for plotting.
  std::string trace;
  tracking::TrackerParams tracker;
  std::string loss = "huber";
};

// Produces frame i (depth + reference pose), or an error.
using FrameSource = std::function<Result<Frame>(std::size_t)>;

struct RunResult {
  std::vector<Pose> estimate, reference;
  Timings tracking, integration;
  Timings tracking_cpu;  // process CPU time of the same calls (all threads): less sensitive to load
  std::size_t lost = 0;
  std::size_t frames = 0;
};

Result<RunResult> trackSequence(const FrameSource& source, std::size_t frames, const volume::VolumeParams& params,
                                const tracking::TrackerParams& tracker_params, const TrackBenchOptions& options) {
  const bool oracle_map = options.oracle_map;
  const bool verbose = options.verbose;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> trace(nullptr, &std::fclose);
  if (!options.trace.empty()) {
    trace.reset(std::fopen(options.trace.c_str(), "w"));
    if (!trace) return makeError("cannot write trace " + options.trace);
    std::fprintf(trace.get(),
                 "frame,status,err_mm,rot_err_deg,ref_step_mm,step_err_mm,step_rot_err_deg,"
                 "inlier_ratio,rms_mm,rcond,iterations,track_ms,est_pose_3x4,ref_pose_3x4\n");
  }
  RunResult run;
  volume::LabeledVolume map(params);
  const tracking::VolumeField field(map);
  tracking::SdfTracker tracker(tracker_params);
  tracking::CameraTrackState state;
  for (std::size_t i = 0; i < frames; ++i) {
    Result<Frame> loaded = source(i);
    if (!loaded) return makeError("frame " + std::to_string(i) + ": " + loaded.error());
    Frame frame = std::move(loaded).value();
    if (!frame.camera_to_world) return makeError("frame " + std::to_string(i) + " has no reference pose");
    const Pose reference = *frame.camera_to_world;
    if (i == 0) {
      state.initial_pose = reference;  // the only reference pose the tracker ever sees
    }
    if (options.depth_scale != 1.0) frame.depth.convertTo(frame.depth, CV_32F, options.depth_scale);
    if (!options.oracle_guess || i == 0) frame.camera_to_world.reset();

    Stopwatch track_watch;
    CpuStopwatch track_cpu;
    Result<tracking::TrackedFrame> tracked = tracking::trackFrame(
        tracker, frame, field, state,
        options.oracle_guess ? tracking::GivenPosePolicy::kRefine : tracking::GivenPosePolicy::kUseAsIs);
    const double track_ms = track_watch.elapsedMs();
    const double track_cpu_ms = track_cpu.elapsedMs();
    if (!tracked) return makeError("frame " + std::to_string(i) + ": " + tracked.error());
    const tracking::TrackedFrame& t = tracked.value();
    if (i > 0) {
      run.tracking.add(track_ms);
      run.tracking_cpu.add(track_cpu_ms);
    }
    if (t.shouldIntegrate()) {
      Stopwatch integrate_watch;
      auto stats = volume::integrate(map, frame.depth, cv::Mat(), frame.intrinsics,
                                     oracle_map ? tracking::orthonormalized(reference) : t.pose);
      run.integration.add(integrate_watch.elapsedMs());
      if (!stats) return makeError("integrate frame " + std::to_string(i) + ": " + stats.error());
    } else {
      ++run.lost;
    }
    if (verbose || !t.shouldIntegrate())
      std::printf(
          "frame %3zu %-11s %-20s inliers %.2f agree %.2f rms %.2f mm rcond %.1e iters %2d %.1f ms  err %.1f mm"
          "  ref step %.1f mm\n",
          i, tracking::toString(t.status), tracking::toString(t.lost_reason), t.quality.inlier_ratio,
          t.quality.observed_agreement, t.quality.rms_residual_m * 1e3, t.quality.hessian_rcond, t.quality.iterations,
          track_ms, (t.pose.translation() - reference.translation()).norm() * 1e3,
          run.reference.empty() ? 0.0 : (reference.translation() - run.reference.back().translation()).norm() * 1e3);
    if (trace) {
      const Pose error = reference.inverse() * t.pose;
      Pose step_error = Pose::Identity();
      double ref_step = 0.0;
      if (!run.reference.empty()) {
        const Pose ref_motion = run.reference.back().inverse() * reference;
        step_error = ref_motion.inverse() * (run.estimate.back().inverse() * t.pose);
        ref_step = ref_motion.translation().norm();
      }
      std::fprintf(trace.get(), "%zu,%s,%.3f,%.4f,%.3f,%.3f,%.4f,%.4f,%.3f,%.3e,%d,%.2f", i,
                   tracking::toString(t.status), (t.pose.translation() - reference.translation()).norm() * 1e3,
                   tracking::rotationAngle(tracking::orthonormalized(error).linear()) * 180.0 / M_PI, ref_step * 1e3,
                   step_error.translation().norm() * 1e3,
                   tracking::rotationAngle(tracking::orthonormalized(step_error).linear()) * 180.0 / M_PI,
                   t.quality.inlier_ratio, t.quality.rms_residual_m * 1e3, t.quality.hessian_rcond,
                   t.quality.iterations, track_ms);
      for (const Pose* pose : {&t.pose, &reference})
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 4; ++c) std::fprintf(trace.get(), ",%.7f", pose->matrix()(r, c));
      std::fputc('\n', trace.get());
    }
    run.estimate.push_back(t.pose);
    run.reference.push_back(reference);
    ++run.frames;
  }
  return run;
}

// Local agreement of a trajectory with the depth, independent of drift: every `step`-th frame is
// aligned, from its own pose, to a map of its `half_window` neighbours on either side fused at
// their poses of the same trajectory. A trajectory the depth supports moves little.
struct Consistency {
  double translation_rms_m = 0.0;
  double rotation_rms_deg = 0.0;
  double residual_mean_m = 0.0;
  std::size_t samples = 0;
};

Result<Consistency> localConsistency(const FrameSource& source, const std::vector<Pose>& poses,
                                     const volume::VolumeParams& params, const tracking::TrackerParams& tracker_params,
                                     std::size_t half_window, std::size_t step) {
  Consistency out;
  tracking::SdfTracker tracker(tracker_params);
  double t_sq = 0.0, r_sq = 0.0, residual = 0.0;
  for (std::size_t i = half_window; i + half_window < poses.size(); i += step) {
    volume::LabeledVolume map(params);
    for (std::size_t j = i - half_window; j <= i + half_window; ++j) {
      if (j == i) continue;
      Result<Frame> neighbour = source(j);
      if (!neighbour) return makeError(neighbour.error());
      auto stats = volume::integrate(map, neighbour.value().depth, cv::Mat(), neighbour.value().intrinsics, poses[j]);
      if (!stats) return makeError(stats.error());
    }
    Result<Frame> frame = source(i);
    if (!frame) return makeError(frame.error());
    auto aligned = tracker.align(frame.value().depth, frame.value().intrinsics, tracking::VolumeField(map), poses[i]);
    if (!aligned) return makeError(aligned.error());
    const Pose pull = poses[i].inverse() * aligned.value().pose;
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

int reportConsistency(const FrameSource& source, const RunResult& run, const volume::VolumeParams& params,
                      const tracking::TrackerParams& tracker_params) {
  constexpr std::size_t kHalfWindow = 20, kStep = 5;
  std::vector<Pose> reference;
  for (const Pose& pose : run.reference) reference.push_back(tracking::orthonormalized(pose));
  Table table("local consistency with the depth: frame aligned to its " + std::to_string(2 * kHalfWindow) +
              " neighbours fused at the same trajectory (every " + std::to_string(kStep) + "th frame)");
  for (const auto& [name, poses] : {std::pair<std::string, const std::vector<Pose>*>{"tracked poses", &run.estimate},
                                    {"reference poses", &reference}}) {
    auto result = localConsistency(source, *poses, params, tracker_params, kHalfWindow, kStep);
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

int report(const std::string& title, const RunResult& run, const std::string& ate_target, bool drift) {
  auto raw = tracking::absoluteTrajectoryError(run.estimate, run.reference, false);
  auto aligned = tracking::absoluteTrajectoryError(run.estimate, run.reference, true);
  auto rpe = tracking::relativePoseError(run.estimate, run.reference);
  if (!raw || !aligned || !rpe) {
    std::fprintf(stderr, "%s: not enough frames for the metrics\n", title.c_str());
    return 1;
  }
  const double path = tracking::pathLength(run.reference);
  Table table(title);
  table.add("frames (tracked from frame 1)", std::to_string(run.frames));
  table.add("ATE RMSE, no alignment", formatNumber(raw.value().rmse_m * 100, 2) + " cm",
            ate_target + "; max " + formatNumber(raw.value().max_m * 100, 2) + " cm");
  table.add("ATE RMSE, Umeyama-aligned", formatNumber(aligned.value().rmse_m * 100, 2) + " cm");
  table.add("RPE per frame, translation", formatNumber(rpe.value().translation_rmse_m * 1000, 2) + " mm",
            "RMSE; max " + formatNumber(rpe.value().translation_max_m * 1000, 2) + " mm (frame " +
                std::to_string(rpe.value().translation_max_frame) + ")");
  table.add("RPE per frame, rotation", formatNumber(rpe.value().rotation_rmse_deg, 3) + " deg",
            "RMSE; max " + formatNumber(rpe.value().rotation_max_deg, 3) + " deg");
  if (drift) {
    const double end_error = (run.estimate.back().translation() - run.reference.back().translation()).norm();
    table.add("path length", formatNumber(path, 2) + " m");
    table.add("drift per metre (end error / path)", formatNumber(end_error / path * 100, 3) + " %",
              "end error " + formatNumber(end_error * 1000, 2) + " mm");
  }
  table.add("frames lost", std::to_string(run.lost), "target 0");
  table.addMs("tracking ms/frame", run.tracking, "target median <= 15 ms (640x480)");
  table.addMs("tracking CPU ms/frame", run.tracking_cpu, "all threads; load average " + formatNumber(loadAverage(), 1));
  table.addMs("integration ms/frame", run.integration, "at the tracked pose");
  table.print();
  return 0;
}

int runTrackBench(const TrackBenchOptions& options) {
  keepScratchResident();  // as semfuse-server does, whose work this times
  volume::VolumeParams params;
  params.voxel_size = options.voxel;
  params.truncation = options.truncation;
  params.integrate_color = false;
  if (Status status = params.validate(); !status) {
    std::fprintf(stderr, "volume parameters: %s\n", status.error().c_str());
    return 2;
  }
  if (!(options.depth_scale > 0.0) || !std::isfinite(options.depth_scale) || !(options.focal >= 0.0) ||
      !std::isfinite(options.focal)) {
    std::fprintf(stderr, "--depth-scale must be finite and > 0, --focal finite and >= 0 (0 = the dataset's)\n");
    return 2;
  }
  tracking::TrackerParams tracker_params = options.tracker;
  if (options.loss == "cauchy") tracker_params.loss = tracking::RobustLoss::kCauchy;
  if (Status status = tracking::SdfTracker::validate(tracker_params); !status) {
    std::fprintf(stderr, "tracker parameters: %s\n", status.error().c_str());
    return 2;
  }
  const auto& p = tracker_params;
  std::printf(
      "voxel %.3f m, truncation %.3f m; tracker: %d levels, points %zu/%zu/%zu, iterations %d/%d/%d, %s %.2f x trunc,"
      " depth <= %.1f m\n",
      options.voxel, options.truncation, p.pyramid.levels, p.pyramid.max_points[0], p.pyramid.max_points[1],
      p.pyramid.max_points[2], p.max_iterations[0], p.max_iterations[1], p.max_iterations[2], options.loss.c_str(),
      static_cast<double>(p.robust_scale), static_cast<double>(p.pyramid.max_depth_m));

  int exit_code = 0;
  if (!options.skip_seven_scenes) {
    datasets::SevenScenesOptions reader_options;
    if (options.focal > 0.0) {
      auto intrinsics =
          datasets::readSevenScenesIntrinsics(std::filesystem::path(options.data) / "camera-intrinsics.txt");
      if (!intrinsics) {
        std::fprintf(stderr, "7-Scenes: %s\n", intrinsics.error().c_str());
        return 2;
      }
      reader_options.intrinsics = intrinsics.value();
      reader_options.intrinsics->fx = reader_options.intrinsics->fy = options.focal;
    }
    auto reader = datasets::SevenScenesReader::open(options.data, reader_options);
    if (!reader) {
      std::fprintf(stderr, "7-Scenes: %s\n", reader.error().c_str());
      return 2;
    }
    const datasets::SevenScenesReader& r = reader.value();
    const std::size_t shift = static_cast<std::size_t>(std::abs(options.pose_offset));
    const std::size_t frames = std::min(options.frames, r.count() - std::min(shift, r.count()));
    const int offset = options.pose_offset;
    const FrameSource source = [&r, offset, shift](std::size_t i) -> Result<Frame> {
      const std::size_t depth_index = offset < 0 ? i + shift : i;
      const std::size_t pose_index = offset > 0 ? i + shift : i;
      Result<Frame> frame = r.loadDepthOnly(depth_index);
      if (!frame || depth_index == pose_index) return frame;
      auto pose = datasets::readSevenScenesPose(r.posePath(pose_index));
      if (!pose) return makeError(pose.error());
      frame.value().camera_to_world = pose.value();
      return frame;
    };
    auto run = trackSequence(source, frames, params, tracker_params, options);
    if (!run) {
      std::fprintf(stderr, "7-Scenes: %s\n", run.error().c_str());
      return 1;
    }
    exit_code |= report("tracking: 7-Scenes redkitchen frames 0-" + std::to_string(frames - 1) + " vs reference poses" +
                            (options.oracle_map ? " (map at reference poses)" : ""),
                        run.value(), "target <= 3 cm", false);
    if (options.consistency) exit_code |= reportConsistency(source, run.value(), params, tracker_params);
  }
  if (!options.skip_synthetic) {
    synthetic::SequenceConfig config;
    config.trajectory.frame_count = options.synthetic_frames;
    const synthetic::SyntheticSequence sequence(config);
    // One trace file: the 7-Scenes run's, or the synthetic run's when 7-Scenes is skipped.
    TrackBenchOptions synthetic_options = options;
    if (!options.skip_seven_scenes) synthetic_options.trace.clear();
    auto run =
        trackSequence([&sequence](std::size_t i) { return sequence.frame(static_cast<int>(i)); },
                      static_cast<std::size_t>(sequence.frameCount()), params, tracker_params, synthetic_options);
    if (!run) {
      std::fprintf(stderr, "synthetic: %s\n", run.error().c_str());
      return 1;
    }
    exit_code |= report(
        "tracking: synthetic room, exact depth, " + std::to_string(sequence.frameCount()) + " frames vs true poses",
        run.value(), "target <= 1 cm", true);
  }
  return exit_code;
}

const bool registered = registerBench(
    "track", "camera tracking by SDF alignment: ATE/RPE on 7-Scenes and the synthetic room", [](CLI::App& command) {
      auto options = std::make_shared<TrackBenchOptions>();
      command.add_option("--data", options->data, "7-Scenes sequence folder")->capture_default_str();
      command.add_option("--frames", options->frames, "7-Scenes frames to track (from frame 0)")->capture_default_str();
      command.add_option("--voxel", options->voxel, "voxel size, metres")->capture_default_str();
      command.add_option("--trunc", options->truncation, "truncation, metres")->capture_default_str();
      command.add_option("--synthetic-frames", options->synthetic_frames, "frames of the synthetic orbit")
          ->capture_default_str();
      command.add_flag("--skip-7scenes", options->skip_seven_scenes, "only the synthetic room");
      command.add_flag("--skip-synthetic", options->skip_synthetic, "only 7-Scenes");
      auto& tp = options->tracker;
      command.add_option("--fine-points", tp.pyramid.max_points[0], "points at 640x480 (0 = all)")
          ->capture_default_str();
      command.add_option("--mid-points", tp.pyramid.max_points[1], "points at 320x240")->capture_default_str();
      command.add_option("--coarse-points", tp.pyramid.max_points[2], "points at 160x120")->capture_default_str();
      command.add_option("--fine-iters", tp.max_iterations[0], "iterations at 640x480")->capture_default_str();
      command.add_option("--mid-iters", tp.max_iterations[1], "iterations at 320x240")->capture_default_str();
      command.add_option("--coarse-iters", tp.max_iterations[2], "iterations at 160x120")->capture_default_str();
      command.add_option("--loss", options->loss, "robust loss")
          ->check(CLI::IsMember({"huber", "cauchy"}))
          ->capture_default_str();
      command.add_option("--robust-scale", tp.robust_scale, "robust scale, x truncation")->capture_default_str();
      command.add_option("--max-depth", tp.pyramid.max_depth_m, "depth readings beyond are ignored, metres")
          ->capture_default_str();
      command.add_option("--convergence", tp.convergence_norm, "update norm that ends a level")->capture_default_str();
      command.add_flag("--oracle-map", options->oracle_map,
                       "diagnostic: integrate at the reference poses (measures per-frame disagreement, not drift)");
      command.add_flag("--oracle-guess", options->oracle_guess,
                       "diagnostic: start each alignment at the reference pose (refinement)");
      command.add_option("--depth-scale", options->depth_scale, "diagnostic: multiply the depth by this")
          ->capture_default_str();
      command.add_option("--focal", options->focal, "diagnostic: 7-Scenes focal length fx = fy, pixels")
          ->capture_default_str();
      command
          .add_option("--pose-offset", options->pose_offset,
                      "diagnostic: pair depth frame i with reference pose i + offset")
          ->capture_default_str();
      command.add_flag("--consistency", options->consistency,
                       "diagnostic: how far the depth pulls each frame of the tracked and the reference trajectory "
                       "from a map of its 40 neighbours (minutes)");
      command.add_option("--trace", options->trace,
                         "write one CSV line per frame (7-Scenes run, else synthetic) to this file");
      command.add_flag("--verbose", options->verbose, "one line per frame (lost frames are always printed)");
      return [options] { return runTrackBench(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
