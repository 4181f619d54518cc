#include "experiments.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include <spdlog/spdlog.h>

#include "percent_text.hpp"

namespace semfuse::eval {
namespace {
namespace fs = std::filesystem;
using volume::LabelRule;

const char* kindName(LabelSourceKind kind) {
  switch (kind) {
    case LabelSourceKind::kTruth:
      return "truth";
    case LabelSourceKind::kPixel:
      return "pixel";
    case LabelSourceKind::kRegion:
      return "region";
    case LabelSourceKind::kSimulatedCnn:
      return "simulated-cnn";
    case LabelSourceKind::kSegmenter:
      return "deeplab";
  }
  return "unknown";
}

std::string fixed(double value, int digits = 4) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

class File {
 public:
  explicit File(const fs::path& path) : path_(path), out_(path) {}
  template <typename T>
  File& operator<<(const T& value) {
    out_ << value;
    return *this;
  }
  Status close() {
    out_.close();
    if (!out_) return makeError("cannot write " + path_.string());
    spdlog::info("wrote {}", path_.string());
    return Status::Ok();
  }

 private:
  fs::path path_;
  std::ofstream out_;
};

double meanOf(const std::vector<double>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

}  // namespace

Experiments::Experiments(ExperimentOptions options, std::vector<Dataset> datasets, ProgressFn progress)
    : options_(std::move(options)), datasets_(std::move(datasets)), progress_(std::move(progress)) {}

Result<ErrorSummary> Experiments::meanError(const Dataset& dataset, const volume::VolumeParams& params,
                                            const LabelSource& source, PassCost* cost, double* sidecar_bytes) {
  std::vector<double> errors;
  for (std::size_t r = 0; r < dataset.runs.size(); ++r) {
    LabelSource run_source = source;
    run_source.seed = source.seed + 1000 * r;  // independent noise per run
    auto outcome = dataset.runs[r]->run(params, run_source);
    if (!outcome) return makeError(dataset.name + ": " + outcome.error());
    errors.push_back(outcome.value().error.fraction());
    if (cost) {
      cost->wall_s += outcome.value().cost.wall_s;
      cost->cpu_s += outcome.value().cost.cpu_s;
      cost->frames += outcome.value().cost.frames;
    }
    if (sidecar_bytes) *sidecar_bytes = outcome.value().sidecar_bytes_per_voxel;
  }
  ErrorSummary s;
  s.runs = errors.size();
  s.mean = meanOf(errors);
  s.min = errors.empty() ? 0.0 : *std::min_element(errors.begin(), errors.end());
  s.max = errors.empty() ? 0.0 : *std::max_element(errors.begin(), errors.end());
  return s;
}

Status Experiments::noiseSweep(LabelSourceKind kind) {
  const std::string stem = kind == LabelSourceKind::kPixel ? "exp1_pixel_noise" : "exp2_region_noise";
  File csv(options_.out / (stem + ".csv"));
  csv << "dataset,noise_model,rule,noise,error_mean,error_min,error_max,runs\n";
  const std::size_t total = datasets_.size() * options_.rules.size() * options_.noise_levels.size();
  std::size_t done = 0;
  for (const Dataset& dataset : datasets_)
    for (LabelRule rule : options_.rules)
      for (double p : options_.noise_levels) {
        volume::VolumeParams params = dataset.params;
        params.label_rule = rule;
        // These noise models label at full confidence, where one bayes increment is exactly 1,
        // the majority rule's: the two volumes are identical, so bayes reuses majority's run.
        const auto majority = sweep_.find({kind, dataset.name, LabelRule::kMajority, p});
        Result<ErrorSummary> error = ErrorSummary{};
        if (rule == LabelRule::kBayes && majority != sweep_.end()) error = majority->second;
        else error = meanError(dataset, params, LabelSource{kind, p, options_.seed});
        if (!error) return makeError(error.error());
        sweep_[{kind, dataset.name, rule, p}] = error.value();
        csv << dataset.name << ',' << kindName(kind) << ',' << volume::labelRuleName(rule) << ',' << p << ','
            << fixed(error.value().mean, 5) << ',' << fixed(error.value().min, 5) << ',' << fixed(error.value().max, 5)
            << ',' << error.value().runs << '\n';
        progress_(stem, ++done, total);
      }
  if (Status s = csv.close(); !s) return s;

  // Plot table: one column per dataset and rule.
  File dat(options_.out / (stem + ".dat"));
  dat << "noise";
  for (const Dataset& dataset : datasets_)
    for (LabelRule rule : options_.rules) dat << ' ' << dataset.name << '-' << volume::labelRuleName(rule);
  dat << '\n';
  for (double p : options_.noise_levels) {
    dat << 100.0 * p;
    for (const Dataset& dataset : datasets_)
      for (LabelRule rule : options_.rules) dat << ' ' << 100.0 * sweep_[{kind, dataset.name, rule, p}].mean;
    dat << '\n';
  }
  return dat.close();
}

Status Experiments::perFrameVsVolumetric() {
  File csv(options_.out / "exp3_per_frame_vs_volumetric.csv");
  csv << "dataset,segmenter,per_frame_mean,per_frame_std,rule,volumetric\n";
  std::size_t done = 0;
  for (const Dataset& dataset : datasets_) {
    const bool real = !dataset.runs.empty() && !dataset.runs[0]->sequence().segmentations.empty();
    const LabelSource source = real ? LabelSource{LabelSourceKind::kSegmenter, 0.0, options_.seed}
                                    : LabelSource{LabelSourceKind::kSimulatedCnn, options_.cnn_noise, options_.seed};
    PerFrameResult result;
    result.dataset = dataset.name;
    result.source =
        real ? "DeepLabV3-MNv2 ADE20K 257" : "simulated CNN (region noise " + percent(options_.cnn_noise) + ")";
    std::vector<double> per_frame;
    for (std::size_t r = 0; r < dataset.runs.size(); ++r) {
      const EvalSequence& sequence = dataset.runs[r]->sequence();
      LabelSource run_source = source;
      run_source.seed = source.seed + 1000 * r;
      for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
        auto labels = labelsFor(sequence, i, run_source);
        if (!labels) return makeError(labels.error());
        if (labels.value().labels.empty()) continue;  // the segmenter did not run on this frame
        auto error = pixelLabelError(sequence.truth[i], labels.value().labels);
        if (!error) return makeError(sequence.name + " frame " + std::to_string(i) + ": " + error.error());
        if (error.value().compared > 0) per_frame.push_back(error.value().fraction());
      }
    }
    result.per_frame_mean = meanOf(per_frame);
    double sum = 0.0;
    for (double e : per_frame) sum += (e - result.per_frame_mean) * (e - result.per_frame_mean);
    result.per_frame_std = per_frame.size() > 1 ? std::sqrt(sum / static_cast<double>(per_frame.size() - 1)) : 0.0;
    for (LabelRule rule : options_.rules) {
      volume::VolumeParams params = dataset.params;
      params.label_rule = rule;
      double volumetric = 0.0;
      if (real) {
        // The real segmenter against the reference labeling (same geometry, its own labels).
        auto outcome = dataset.runs[0]->run(params, source, *dataset.runs[0]->sequence().reference_labeling);
        if (!outcome) return makeError(outcome.error());
        volumetric = outcome.value().error.fraction();
      } else {
        auto error = meanError(dataset, params, source);
        if (!error) return makeError(error.error());
        volumetric = error.value().mean;
      }
      result.volumetric[rule] = volumetric;
      csv << dataset.name << ",\"" << result.source << "\"," << fixed(result.per_frame_mean, 5) << ','
          << fixed(result.per_frame_std, 5) << ',' << volume::labelRuleName(rule) << ',' << fixed(volumetric, 5)
          << '\n';
      progress_("exp3_per_frame_vs_volumetric", ++done, datasets_.size() * options_.rules.size());
    }
    per_frame_.push_back(result);
  }
  return csv.close();
}

Status Experiments::rulesSideBySide() {
  if (datasets_.empty()) return makeError("no dataset");
  const Dataset& dataset = datasets_.front();
  File csv(options_.out / "exp4_rules.csv");
  csv << "rule,bytes_per_voxel,measured_bytes_per_voxel,label_pass_ms_per_frame,label_pass_cpu_ms_per_frame,"
         "cost_vs_evidence,error_pixel50,error_pixel70,error_region50\n";
  double evidence_cpu = 0.0;
  std::size_t done = 0;
  for (LabelRule rule : options_.rules) {
    volume::VolumeParams params = dataset.params;
    params.label_rule = rule;
    PassCost cost;
    double sidecar = 0.0;
    // The cost of a label pass at 50% pixel noise, the same work for every rule.
    auto error = meanError(dataset, params, LabelSource{LabelSourceKind::kPixel, 0.5, options_.seed}, &cost, &sidecar);
    if (!error) return makeError(error.error());
    const volume::LabeledVolume& geometry = dataset.runs[0]->geometry();
    RuleCost rc{
        rule, static_cast<double>(volume::labelRuleBytesPerVoxel(rule)),
        static_cast<double>(geometry.geometryMemoryBytes()) / static_cast<double>(geometry.allocatedVoxels()) + sidecar,
        1000.0 * cost.wall_s / static_cast<double>(cost.frames),
        1000.0 * cost.cpu_s / static_cast<double>(cost.frames)};
    if (rule == LabelRule::kEvidence) evidence_cpu = rc.cpu_ms_per_frame;
    costs_.push_back(rc);
    auto at = [&](LabelSourceKind kind, double p) {
      auto found = sweep_.find({kind, dataset.name, rule, p});
      return found == sweep_.end() ? std::string("") : fixed(found->second.mean, 5);
    };
    csv << volume::labelRuleName(rule) << ',' << rc.nominal_bytes << ',' << fixed(rc.measured_bytes, 2) << ','
        << fixed(rc.wall_ms_per_frame, 3) << ',' << fixed(rc.cpu_ms_per_frame, 3) << ','
        << (evidence_cpu > 0 ? fixed(rc.cpu_ms_per_frame / evidence_cpu, 2) : std::string("")) << ','
        << at(LabelSourceKind::kPixel, 0.5) << ',' << at(LabelSourceKind::kPixel, 0.7) << ','
        << at(LabelSourceKind::kRegion, 0.5) << '\n';
    progress_("exp4_rules", ++done, options_.rules.size());
  }
  return csv.close();
}

Status Experiments::sensitivity() {
  if (datasets_.empty() || datasets_.front().runs.empty()) return makeError("no dataset");
  Dataset dataset = datasets_.front();
  dataset.runs.resize(1);  // one run: the sweep multiplies the passes
  File clamp_csv(options_.out / "exp5_clamp.csv");
  clamp_csv << "dataset,rule,w_clamp,error_pixel50,error_simulated_cnn\n";
  std::size_t done = 0;
  const std::size_t total = options_.rules.size() * (options_.clamps.size() + 3);
  for (LabelRule rule : options_.rules)
    for (float clamp : options_.clamps) {
      volume::VolumeParams params = dataset.params;
      params.label_rule = rule;
      params.max_label_score = clamp;
      auto pixel = meanError(dataset, params, LabelSource{LabelSourceKind::kPixel, 0.5, options_.seed});
      if (!pixel) return makeError(pixel.error());
      auto cnn =
          meanError(dataset, params, LabelSource{LabelSourceKind::kSimulatedCnn, options_.cnn_noise, options_.seed});
      if (!cnn) return makeError(cnn.error());
      clamp_[{rule, clamp}] = {pixel.value().mean, cnn.value().mean};
      clamp_csv << dataset.name << ',' << volume::labelRuleName(rule) << ',' << clamp << ','
                << fixed(pixel.value().mean, 5) << ',' << fixed(cnn.value().mean, 5) << '\n';
      progress_("exp5_sensitivity", ++done, total);
    }
  if (Status s = clamp_csv.close(); !s) return s;
  File dat(options_.out / "exp5_clamp.dat");
  dat << "w_clamp";
  for (LabelRule rule : options_.rules) dat << " pixel50-" << volume::labelRuleName(rule);
  for (LabelRule rule : options_.rules) dat << " cnn-" << volume::labelRuleName(rule);
  dat << '\n';
  for (float clamp : options_.clamps) {
    dat << clamp;
    for (LabelRule rule : options_.rules) dat << ' ' << 100.0 * clamp_[{rule, clamp}].first;
    for (LabelRule rule : options_.rules) dat << ' ' << 100.0 * clamp_[{rule, clamp}].second;
    dat << '\n';
  }
  if (Status s = dat.close(); !s) return s;

  File weight_csv(options_.out / "exp5_weight.csv");
  weight_csv << "dataset,rule,weight,error_simulated_cnn\n";
  for (LabelRule rule : options_.rules)
    for (WeightMode mode : {WeightMode::kConfidence, WeightMode::kConstant, WeightMode::kSquared}) {
      volume::VolumeParams params = dataset.params;
      params.label_rule = rule;
      auto cnn = meanError(dataset, params,
                           LabelSource{LabelSourceKind::kSimulatedCnn, options_.cnn_noise, options_.seed, mode});
      if (!cnn) return makeError(cnn.error());
      weight_[{rule, mode}] = cnn.value().mean;
      weight_csv << dataset.name << ',' << volume::labelRuleName(rule) << ',' << weightModeName(mode) << ','
                 << fixed(cnn.value().mean, 5) << '\n';
      progress_("exp5_sensitivity", ++done, total);
    }
  return weight_csv.close();
}

}  // namespace semfuse::eval
