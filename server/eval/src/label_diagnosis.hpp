#pragma once
// What limits a rule's volumetric error (docs/eval experiment 6): for every surface voxel, how many observations
// it got, whether it sits on a label border, and what an exact count of every label it was shown
// (an oracle no bounded-memory rule can beat on independent noise) would have decided. Errors of
// the rule that the oracle avoids are the rule's own (list truncation, clamp, fixed point); errors
// both make come from too few observations or labels that genuinely compete at the voxel.
//
// The exact counts come from the integrator itself, so visibility and projection are the
// server's: one label pass per label present, where that label's pixels become label 1 and every
// other pixel unlabeled, fused with the majority rule and a clamp no count reaches; the voxel's
// score is then the number of times it was shown that label.
#include <cstddef>
#include <string>
#include <vector>

#include "label_passes.hpp"

namespace semfuse::eval {

// Observation-count bins of the histogram: [lower, next lower).
inline const std::vector<int>& observationBins() {
  static const std::vector<int> bins{0, 1, 5, 10, 20, 40, 80};
  return bins;
}

struct DiagnosisBin {
  int lower = 0;                 // observations, inclusive
  std::size_t voxels = 0;        // surface voxels the reference labels with this many observations
  std::size_t rule_wrong = 0;    // the rule's label differs from its noise-free reference
  std::size_t oracle_wrong = 0;  // the exact-count argmax differs from it
};

struct LabelDiagnosis {
  std::vector<DiagnosisBin> bins;
  std::size_t voxels = 0, rule_wrong = 0, oracle_wrong = 0;
  std::size_t border_voxels = 0;  // noise-free counts: the top label has < 80% of them
  std::size_t border_rule_wrong = 0;
  std::size_t rule_only_wrong = 0;    // the oracle is right: truncation / clamp / fixed point
  std::size_t oracle_only_wrong = 0;  // the rule is right where the oracle is not (ties, luck)
};

// Exact per-voxel counts of each label present in the sequence, for the scenario's surface
// voxels in order, voxel-major: counts[v * labels.size() + l].
struct ExactCounts {
  std::vector<LabelId> labels;
  std::vector<float> counts;
  const float* of(std::size_t voxel) const { return counts.data() + voxel * labels.size(); }
};
Result<ExactCounts> countLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                const LabelSource& source);

// Diagnoses `params`' rule on `source` (pixel or region noise, or the truth) in one scenario,
// given the exact counts of the truth and of the source (from countLabels, which do not depend
// on the rule). The oracle is right where the reference's label has strictly the largest count:
// a tie counts against it, so "rule wrong, oracle right" is the rule's own loss.
Result<LabelDiagnosis> diagnoseLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                      const LabelSource& source, const ExactCounts& clean, const ExactCounts& noisy);
// The same, counting first.
Result<LabelDiagnosis> diagnoseLabels(const Scenario& scenario, const volume::VolumeParams& params,
                                      const LabelSource& source);

// The share of observations of a voxel's top label below which it counts as a border voxel.
inline constexpr double kBorderShare = 0.8;

}  // namespace semfuse::eval
