// Experiment 6: what limits each rule's error under pixel noise (label_diagnosis.hpp), summed
// over a dataset's runs, as exp6_diagnosis.csv and a section of the summary.
#include <algorithm>
#include <fstream>

#include <spdlog/spdlog.h>

#include "experiments.hpp"

namespace semfuse::eval {
namespace {

constexpr std::size_t kMaxDiagnosedLabels = 16;

void add(LabelDiagnosis& sum, const LabelDiagnosis& d) {
  if (sum.bins.empty()) sum.bins = d.bins;
  else
    for (std::size_t i = 0; i < d.bins.size(); ++i) {
      sum.bins[i].voxels += d.bins[i].voxels;
      sum.bins[i].rule_wrong += d.bins[i].rule_wrong;
      sum.bins[i].oracle_wrong += d.bins[i].oracle_wrong;
    }
  sum.voxels += d.voxels, sum.rule_wrong += d.rule_wrong, sum.oracle_wrong += d.oracle_wrong;
  sum.border_voxels += d.border_voxels, sum.border_rule_wrong += d.border_rule_wrong;
  sum.rule_only_wrong += d.rule_only_wrong, sum.oracle_only_wrong += d.oracle_only_wrong;
}

}  // namespace

Status Experiments::diagnosis(const std::vector<double>& pixel_noise) {
  const auto path = options_.out / "exp6_diagnosis.csv";
  std::ofstream csv(path);
  csv << "dataset,rule,noise,observations_from,surface_voxels,rule_wrong,oracle_wrong\n";
  // Full-confidence labels: one bayes increment is one majority count, so the two rules give the
  // same volume (as in experiment 1) and bayes reuses majority's diagnosis.
  using volume::LabelRule;
  const bool bayes_is_majority =
      std::find(options_.rules.begin(), options_.rules.end(), LabelRule::kMajority) != options_.rules.end();
  std::size_t done = 0, total = 0;
  for (const Dataset& dataset : datasets_) total += dataset.runs.size() * pixel_noise.size();
  for (const Dataset& dataset : datasets_) {
    // One counting pass per label present: affordable on the synthetic room (7 labels), not on
    // the 7-Scenes reference labeling (dozens).
    if (dataset.runs.empty() || dataset.runs.front()->sequence().present_labels.size() > kMaxDiagnosedLabels) {
      spdlog::info("exp6_diagnosis: {} skipped (more than {} labels)", dataset.name, kMaxDiagnosedLabels);
      continue;
    }
    for (std::size_t r = 0; r < dataset.runs.size(); ++r) {
      const Scenario& scenario = *dataset.runs[r];
      auto clean = countLabels(scenario, dataset.params, LabelSource{});
      if (!clean) return makeError(dataset.name + ": " + clean.error());
      for (double p : pixel_noise) {
        // The same seeds as experiment 1, so the rule's errors here are that experiment's.
        const LabelSource source{LabelSourceKind::kPixel, p, options_.seed + 1000 * r};
        auto noisy = countLabels(scenario, dataset.params, source);
        if (!noisy) return makeError(dataset.name + ": " + noisy.error());
        for (volume::LabelRule rule : options_.rules) {
          if (rule == volume::LabelRule::kBayes && bayes_is_majority) continue;  // copied below
          volume::VolumeParams params = dataset.params;
          params.label_rule = rule;
          auto d = diagnoseLabels(scenario, params, source, clean.value(), noisy.value());
          if (!d) return makeError(dataset.name + ": " + d.error());
          add(diagnosis_[{dataset.name, rule, p}], d.value());
        }
        progress_("exp6_diagnosis", ++done, total);
      }
    }
    for (double p : pixel_noise)
      if (bayes_is_majority)
        diagnosis_[{dataset.name, LabelRule::kBayes, p}] = diagnosis_[{dataset.name, LabelRule::kMajority, p}];
    for (volume::LabelRule rule : options_.rules)
      for (double p : pixel_noise)
        for (const DiagnosisBin& b : diagnosis_[{dataset.name, rule, p}].bins)
          csv << dataset.name << ',' << volume::labelRuleName(rule) << ',' << p << ',' << b.lower << ',' << b.voxels
              << ',' << b.rule_wrong << ',' << b.oracle_wrong << '\n';
  }
  csv.close();
  if (!csv) return makeError("cannot write " + path.string());
  spdlog::info("wrote {}", path.string());
  return Status::Ok();
}

}  // namespace semfuse::eval
