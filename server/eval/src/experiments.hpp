#pragma once
// The label fusion experiments of docs/eval, on scenarios prepared by the caller, each writing a CSV (and a
// plot table) into the output folder; results are also kept for the markdown summary.
//  1 pixel noise (the paper's model)      -> exp1_pixel_noise.csv / .dat
//  2 region noise (structured)            -> exp2_region_noise.csv / .dat
//  3 per-frame vs volumetric              -> exp3_per_frame_vs_volumetric.csv
//  4 fusion rules side by side            -> exp4_rules.csv
//  5 sensitivity to W_clamp and weights   -> exp5_clamp.csv / .dat, exp5_weight.csv (first run only)
//  6 what limits the error (diagnosis)     -> exp6_diagnosis.csv
#include <filesystem>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "label_diagnosis.hpp"
#include "label_passes.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse::eval {

struct Dataset {
  std::string name;             // "synthetic", "7scenes"
  std::vector<Scenario*> runs;  // seeds / trajectories; errors are averaged over them
  volume::VolumeParams params;  // voxel size etc. of this dataset
};

struct ExperimentOptions {
  std::filesystem::path out;
  std::vector<double> noise_levels;
  std::vector<volume::LabelRule> rules;
  double cnn_noise = 0.35;  // region-switch probability of the simulated CNN
  std::vector<float> clamps{4, 16, 64, 256};
  uint64_t seed = 1;
};

// One result line: mean of the runs' errors.
struct ErrorSummary {
  double mean = 0.0, min = 0.0, max = 0.0;
  std::size_t runs = 0;
};

struct PerFrameResult {
  std::string dataset, source;
  double per_frame_mean = 0.0, per_frame_std = 0.0;
  std::map<volume::LabelRule, double> volumetric;
};

struct RuleCost {
  volume::LabelRule rule;
  double nominal_bytes = 0.0;   // packed voxel + sidecar per voxel
  double measured_bytes = 0.0;  // (geometry + sidecar memUsage) / allocated voxels
  double wall_ms_per_frame = 0.0, cpu_ms_per_frame = 0.0;
};

class Experiments {
 public:
  using ProgressFn = std::function<void(const std::string& what, std::size_t done, std::size_t total)>;
  Experiments(ExperimentOptions options, std::vector<Dataset> datasets, ProgressFn progress);

  Status noiseSweep(LabelSourceKind kind);                   // experiments 1 (kPixel) and 2 (kRegion)
  Status perFrameVsVolumetric();                             // 3
  Status rulesSideBySide();                                  // 4 (uses 1 and 2 for its error columns)
  Status sensitivity();                                      // 5
  Status diagnosis(const std::vector<double>& pixel_noise);  // 6 (label_diagnosis.hpp)
  Status writeSummary(const std::string& command, const std::string& notes) const;

  // Errors by (kind, dataset, rule, noise); for the summary and tests.
  const std::map<std::tuple<LabelSourceKind, std::string, volume::LabelRule, double>, ErrorSummary>& sweep() const {
    return sweep_;
  }

 private:
  void writeDiagnosis(std::ostream& md) const;  // section 6 of the summary, when run
  Result<ErrorSummary> meanError(const Dataset& dataset, const volume::VolumeParams& params, const LabelSource& source,
                                 PassCost* cost = nullptr, double* sidecar_bytes = nullptr);

  ExperimentOptions options_;
  std::vector<Dataset> datasets_;
  ProgressFn progress_;
  std::map<std::tuple<LabelSourceKind, std::string, volume::LabelRule, double>, ErrorSummary> sweep_;
  std::vector<PerFrameResult> per_frame_;
  std::vector<RuleCost> costs_;
  std::map<std::tuple<volume::LabelRule, float>, std::pair<double, double>> clamp_;  // -> (pixel 50%, cnn)
  std::map<std::tuple<volume::LabelRule, WeightMode>, double> weight_;
  std::map<std::tuple<std::string, volume::LabelRule, double>, LabelDiagnosis> diagnosis_;  // summed over runs
};

}  // namespace semfuse::eval
