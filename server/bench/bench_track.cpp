// semfuse-bench track: the server's camera tracking on recorded sequences and on hard cases made
// from them (frames dropped, a jump, a covered sensor, a view of one plane), in process: every
// frame is tracked without its pose, integrated where the tracker says so, and the integrated
// poses are compared with the sequence's reference (track_report.hpp says how).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "bench_support.hpp"
#include "semfuse/core/malloc_tuning.hpp"
#include "semfuse/tracking/trajectory_metrics.hpp"
#include "track/track_cases.hpp"
#include "track/track_consistency.hpp"
#include "track/track_report.hpp"
#include "track/track_run.hpp"
#include "track/track_sequence.hpp"

namespace semfuse::bench {
namespace {

struct TrackBenchOptions {
  std::vector<std::string> sequences;
  std::vector<std::string> cases;  // empty: the default hard cases for each sequence's length
  std::size_t max_frames = 0;
  double voxel = 0.01;
  double truncation = 0.04;
  bool consistency = false;
  bool color_weight_given = false;  // --color-weight on the command line: used for every sequence
  RunOptions run;
  std::string loss = "huber";
};

std::vector<std::string> defaultSequences() {
  const auto data = sharedDir() / "data";
  return {"tum:" + (data / "rgbd_dataset_freiburg1_xyz").string(), "7scenes:" + (data / "7scenes-redkitchen").string(),
          "synthetic:300"};
}

// Frames dropped (strides 2-8), a jump ahead (as after a dropped link), a kidnap away and back,
// a second of covered sensor and a second of one plane, placed by the sequence's length.
std::vector<std::string> defaultCases(std::size_t n) {
  auto at = [n](double fraction) {
    return std::to_string(static_cast<std::size_t>(fraction * static_cast<double>(n)));
  };
  std::vector<std::string> cases{"full", "stride:2", "stride:4", "stride:8"};
  cases.push_back("jump:0-" + at(0.375) + "," + at(0.625) + "-" + std::to_string(n - 1));
  cases.push_back("jump:0-" + at(0.3) + "," + at(0.7) + "-" + at(0.8) + "," + at(0.3) + "-" + std::to_string(n - 1));
  cases.push_back("covered:" + at(0.5) + "+30");
  cases.push_back("plane:" + at(0.5) + "+30");
  return cases;
}

int benchSequence(const std::string& spec, const TrackBenchOptions& options) {
  Stopwatch load_watch;
  auto loaded = TrackSequence::load(spec, options.max_frames);
  if (!loaded) {
    std::fprintf(stderr, "track: %s\n", loaded.error().c_str());
    return 2;
  }
  const TrackSequence& sequence = loaded.value();
  std::printf("\n%s: %zu frames, reference: %s (loaded in %.1f s)\n", sequence.name().c_str(), sequence.size(),
              sequence.referenceKind().c_str(), load_watch.elapsedMs() / 1000.0);
  RunOptions run_options = options.run;
  if (!sequence.colorRegistered() && !options.color_weight_given) {
    run_options.tracker.alignment.color_weight = 0.0f;
    std::printf("  colour not registered to depth: tracked on depth alone (the server's --track-color-weight 0)\n");
  }

  std::vector<std::string> specs = options.cases.empty() ? defaultCases(sequence.size()) : options.cases;
  std::vector<TrackCase> cases;
  for (const std::string& case_spec : specs) {
    auto made = makeTrackCase(case_spec, sequence.size());
    if (!made) {
      std::fprintf(stderr, "track: %s\n", made.error().c_str());
      return 2;
    }
    cases.push_back(std::move(made).value());
  }

  std::vector<std::optional<Pose>> judge(sequence.size());
  std::string judged_against = "the " + sequence.referenceKind() + " poses";
  std::optional<CaseRun> unbroken;
  if (sequence.referenceIsTruth()) {
    for (std::size_t i = 0; i < sequence.size(); ++i) judge[i] = sequence.reference(i);
  } else {
    // The reference does not agree with the depth well enough to judge a pose by (its own
    // reconstruction's drift); poses are judged against an unbroken run instead.
    auto full = makeTrackCase("full", sequence.size());
    auto run = runCase(sequence, full.value(), run_options);
    if (!run) {
      std::fprintf(stderr, "track: %s: %s\n", sequence.name().c_str(), run.error().c_str());
      return 1;
    }
    std::vector<Pose> estimate, reference;
    for (const FrameRecord& record : run.value().frames) {
      if (!record.integrated()) continue;
      judge[record.index] = record.tracked.pose;
      if (!sequence.reference(record.index)) continue;
      estimate.push_back(record.tracked.pose);
      reference.push_back(*sequence.reference(record.index));
    }
    auto ate = tracking::absoluteTrajectoryError(estimate, reference, true);
    if (ate)
      std::printf("  unbroken run against the %s poses: ATE %.2f cm (max %.2f cm), aligned\n",
                  sequence.referenceKind().c_str(), ate.value().rmse_m * 100.0, ate.value().max_m * 100.0);
    judged_against = "an unbroken tracked run (the " + sequence.referenceKind() + " poses disagree with the depth)";
    unbroken = std::move(run).value();
  }

  // The sequence's own poses, reported beside the judge's when they are not the judge.
  std::vector<std::optional<Pose>> sequence_reference;
  if (!sequence.referenceIsTruth())
    for (std::size_t i = 0; i < sequence.size(); ++i) sequence_reference.push_back(sequence.reference(i));
  std::vector<CaseSummary> rows;
  for (const TrackCase& track_case : cases) {
    std::printf("  case %s\n", track_case.spec.c_str());
    std::fflush(stdout);
    auto run = runCase(sequence, track_case, run_options, judge);
    if (!run) {
      std::fprintf(stderr, "track: %s %s: %s\n", sequence.name().c_str(), track_case.spec.c_str(), run.error().c_str());
      return 1;
    }
    rows.push_back(summarise(track_case, run.value(), judge, sequence_reference));
  }
  printCaseTable("tracking: " + sequence.name() + ", " + std::to_string(sequence.size()) + " frames", judged_against,
                 rows);
  if (options.consistency) {
    if (!unbroken) {
      auto full = makeTrackCase("full", sequence.size());
      auto run = runCase(sequence, full.value(), run_options);
      if (!run) return 1;
      unbroken = std::move(run).value();
    }
    return reportConsistency(sequence, *unbroken, run_options);
  }
  return 0;
}

int runTrackBench(TrackBenchOptions options) {
  keepScratchResident();  // as semfuse-server does, whose work this times
  options.run.volume.voxel_size = options.voxel;
  options.run.volume.truncation = options.truncation;
  if (Status status = options.run.volume.validate(); !status) {
    std::fprintf(stderr, "volume parameters: %s\n", status.error().c_str());
    return 2;
  }
  auto& alignment = options.run.tracker.alignment;
  if (options.loss == "cauchy") alignment.loss = tracking::RobustLoss::kCauchy;
  if (Status status = tracking::SdfTracker::validate(alignment); !status) {
    std::fprintf(stderr, "tracker parameters: %s\n", status.error().c_str());
    return 2;
  }
  std::printf("voxel %.3f m, truncation %.3f m, colour integrated; load average %.1f\n", options.voxel,
              options.truncation, loadAverage());
  if (options.sequences.empty()) options.sequences = defaultSequences();
  int exit_code = 0;
  for (const std::string& spec : options.sequences) exit_code = std::max(exit_code, benchSequence(spec, options));
  return exit_code;
}

const bool track_registered = registerBench(
    "track",
    "camera tracking without poses: ATE/RPE, frames lost, relocalisation and wrong poses on TUM, 7-Scenes and the "
    "synthetic room, unbroken and in hard cases",
    [](CLI::App& command) {
      auto options = std::make_shared<TrackBenchOptions>();
      command
          .add_option("--sequence", options->sequences,
                      "tum:DIR, 7scenes:DIR or synthetic[:N] (repeatable; default: freiburg1_xyz and redkitchen from "
                      "../shared, synthetic:300)")
          ->take_all();
      command
          .add_option("--case", options->cases,
                      "full, stride:K, jump:A-B,C-D,..., covered:S+N, plane:S+N (repeatable; default: full, strides "
                      "2/4/8, a jump ahead, a kidnap and back, 30 covered frames, 30 frames of one plane)")
          ->take_all();
      command.add_option("--frames", options->max_frames, "at most this many frames of each sequence (0 = all)")
          ->capture_default_str();
      command.add_option("--voxel", options->voxel, "voxel size, metres")->capture_default_str();
      command.add_option("--trunc", options->truncation, "truncation, metres")->capture_default_str();
      auto& tp = options->run.tracker.alignment;
      command.add_option("--fine-points", tp.pyramid.max_points[0], "points at 640x480 (0 = all)")
          ->capture_default_str();
      command.add_option("--mid-points", tp.pyramid.max_points[1], "points at 320x240")->capture_default_str();
      command.add_option("--coarse-points", tp.pyramid.max_points[2], "points at 160x120")->capture_default_str();
      command
          .add_option("--odometry-points", options->run.tracker.odometry.max_points[0],
                      "image alignment points at 160x120, its finest level (0 = every pixel with depth)")
          ->capture_default_str();
      command.add_option("--fine-iters", tp.max_iterations[0], "iterations at 640x480")->capture_default_str();
      command.add_option("--mid-iters", tp.max_iterations[1], "iterations at 320x240")->capture_default_str();
      command.add_option("--coarse-iters", tp.max_iterations[2], "iterations at 160x120")->capture_default_str();
      command.add_option("--loss", options->loss, "robust loss")
          ->check(CLI::IsMember({"huber", "cauchy"}))
          ->capture_default_str();
      command.add_option("--robust-scale", tp.robust_scale, "robust scale, x truncation")->capture_default_str();
      auto* color_weight =
          command
              .add_option("--color-weight", tp.color_weight,
                          "weight of the photometric term (0 = depth only; default 0 for 7-Scenes, whose colour is "
                          "not registered to its depth)")
              ->capture_default_str();
      command.add_option("--color-scale", tp.color_robust_scale, "Huber scale of intensity residuals")
          ->capture_default_str();
      command.add_option("--blur", tp.pyramid.intensity_blur_px, "Gaussian blur of the intensity image, pixels")
          ->capture_default_str();
      command.add_option("--solve-rcond", tp.solve_rcond, "directions weaker than this are not solved for")
          ->capture_default_str();
      command.add_option("--max-depth", tp.pyramid.max_depth_m, "depth readings beyond are ignored, metres")
          ->capture_default_str();
      command
          .add_option("--max-rms", tp.max_rms_fraction,
                      "a frame whose inliers' RMS exceeds this, x truncation, is lost")
          ->capture_default_str();
      auto& tc = options->run.tracker;
      command
          .add_option("--max-image-correction", tc.max_image_correction_m,
                      "a pose the SDF alignment moved farther from an image-alignment start needs the map's "
                      "confirmation, metres")
          ->capture_default_str();
      command
          .add_option("--confirm-agreement", tc.confirm_min_agreement,
                      "agreement with the map that confirms a pose on its own")
          ->capture_default_str();
      command.add_option("--depth-scale", options->run.depth_scale, "diagnostic: multiply every depth reading")
          ->capture_default_str();
      command.add_flag("--consistency", options->consistency,
                       "also: how far the depth pulls every 5th frame of the tracked and the reference trajectory "
                       "from a map of its 40 neighbours (minutes)");
      command.add_flag("--verbose", options->run.verbose, "one line per frame (lost and relocalised ones always)");
      return [options, color_weight] {
        options->color_weight_given = color_weight->count() > 0;
        return runTrackBench(*options);
      };
    });

}  // namespace
}  // namespace semfuse::bench
