// semfuse-bench ate: how far a recorded trajectory (`semfuse-query poses --out FILE`, TUM format)
// is from a reference trajectory such as a TUM sequence's motion-capture groundtruth.txt. Each
// estimated pose is paired with the reference interpolated to its time stamp; the errors are the
// TUM benchmark's: ATE after the best rigid alignment of the camera centres, and RPE between
// consecutive paired poses.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_registry.hpp"
#include "semfuse/datasets/tum_trajectory.hpp"
#include "semfuse/tracking/trajectory_metrics.hpp"

namespace semfuse::bench {
namespace {

struct AteOptions {
  std::string estimate;
  std::string reference;
  double window_s = 0.02;
};

int runAte(const AteOptions& options) {
  auto estimate = datasets::readTumTrajectory(options.estimate);
  if (!estimate) {
    std::fprintf(stderr, "ate: estimate: %s\n", estimate.error().c_str());
    return 2;
  }
  auto reference = datasets::readTumTrajectory(options.reference);
  if (!reference) {
    std::fprintf(stderr, "ate: reference: %s\n", reference.error().c_str());
    return 2;
  }
  std::vector<Pose> paired_estimate, paired_reference;
  for (const datasets::TimedPose& pose : estimate.value()) {
    const auto truth = datasets::trajectoryPoseAt(reference.value(), pose.time, options.window_s);
    if (!truth) continue;
    paired_estimate.push_back(pose.pose);
    paired_reference.push_back(*truth);
  }
  std::printf("%zu estimated poses, %zu paired with the reference within %.0f ms\n", estimate.value().size(),
              paired_estimate.size(), options.window_s * 1000.0);
  if (paired_estimate.size() < 3) {
    std::fprintf(stderr, "ate: fewer than 3 poses paired: are both files in seconds of the same clock?\n");
    return 1;
  }
  auto ate = tracking::absoluteTrajectoryError(paired_estimate, paired_reference, /*align=*/true);
  auto rpe = tracking::relativePoseError(paired_estimate, paired_reference);
  if (!ate || !rpe) {
    std::fprintf(stderr, "ate: %s\n", (!ate ? ate.error() : rpe.error()).c_str());
    return 1;
  }
  std::printf("ATE RMSE %.2f cm, mean %.2f cm, max %.2f cm (rigid alignment of the camera centres)\n",
              ate.value().rmse_m * 100.0, ate.value().mean_m * 100.0, ate.value().max_m * 100.0);
  std::printf("RPE per paired step: %.2f mm, %.3f deg RMSE (max %.2f mm, %.2f deg)\n",
              rpe.value().translation_rmse_m * 1000.0, rpe.value().rotation_rmse_deg,
              rpe.value().translation_max_m * 1000.0, rpe.value().rotation_max_deg);
  return 0;
}

const bool ate_registered = registerBench(
    "ate", "trajectory error of a recorded TUM-format trajectory against a reference one (ATE, RPE)",
    [](CLI::App& command) {
      auto options = std::make_shared<AteOptions>();
      command.add_option("--estimate", options->estimate, "estimated trajectory (semfuse-query poses --out FILE)")
          ->required()
          ->check(CLI::ExistingFile);
      command.add_option("--reference", options->reference, "reference trajectory, e.g. a TUM groundtruth.txt")
          ->required()
          ->check(CLI::ExistingFile);
      command.add_option("--window", options->window_s, "largest time difference when pairing poses, seconds")
          ->check(CLI::PositiveNumber)
          ->capture_default_str();
      return [options] { return runAte(*options); };
    });

}  // namespace
}  // namespace semfuse::bench
