#pragma once
// Label fusion rules: how a voxel's label changes when a frame observes it with label `observed`
// and confidence `w`. Every rule leaves its winner in the packed voxel's label/score, so raycast,
// mesh, queries and map files read every rule the same way.
//
//  evidence  Algorithm 1 of Cavallari & Di Stefano (label_fusion.hpp): one label, one score;
//            8 bytes per voxel with geometry.
//  majority  a count of the observations of each of the voxel's top-5 labels (confidence ignored).
//  bayes     the log-probability of each of the top-5 labels under a calibrated likelihood
//            (Kimera-Semantics style): a pixel with confidence c is right with probability
//            p(c) = 1/L + (p_max - 1/L) * c and otherwise any of the L-1 other labels, so the
//            observed label gains log(p(c) (L-1) / (1 - p(c))) over every other label. Scores are in
//            units of one full-confidence observation (a positive scale changes no decision).
//
// The two top-5 rules keep the leader in the packed voxel and four runners-up in a sidecar grid of
// the same topology: 16 bytes per voxel. Each runner-up takes 16 bits of the sidecar: a 10-bit
// label (legends up to 1023 labels: ADE20K-150, COCO-133, NYU-40, VOC-21; observations of larger
// ids are ignored by these rules) and a 6-bit score in fixed point. The fixed point step divides
// one full-confidence observation (1/3 of it at W_clamp 16), so counts stay exact and a runner-up
// never exceeds W_clamp (runners-up are below the leader, which the clamp bounds).
// Measured on the synthetic room with 150 frames per run (docs/eval): the former top-3 layout
// (two 16-bit labels and half scores) lost 6.6% / 35.0% of the surface voxels at 50% / 70% pixel
// noise, this one 6.0% / 29.4%; the rest is observation-bound (experiment 6: an exact count of
// every label loses about as much), so the evaluation now fuses 600 frames per run.
//
// Truncation to 5 labels is the weighted Misra-Gries summary: a label outside a full list takes
// the same amount of evidence from every entry (at most the weakest entry's) and enters with what
// is left once an entry is used up. Every label with more than a sixth of a voxel's evidence is
// tracked. Eroding only the weakest entry instead lets early wrong labels hold their slots for
// good while the true label churns in the last one (measured with three slots: a fifth of the
// voxels stuck at 70% pixel noise). The clamp W_clamp bounds the leader's lead over the untracked
// labels: when a score would pass it, all scores shift down (a log-probability is defined up to a
// constant), which keeps the differences, i.e. the decision, and lets a changed scene be relearned
// in about W_clamp frames.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/volume/label_fusion.hpp"
#include "semfuse/volume/voxel.hpp"

namespace semfuse::volume {

enum class LabelRule { kEvidence, kMajority, kBayes };

Result<LabelRule> parseLabelRule(const std::string& text);  // "evidence", "majority", "bayes"
const char* labelRuleName(LabelRule rule);
// Whether the rule keeps runners-up in the sidecar grid.
inline bool usesLabelSidecar(LabelRule rule) { return rule != LabelRule::kEvidence; }
// Bytes per voxel of the packed voxel (geometry + label) plus the rule's sidecar; colour excluded.
inline std::size_t labelRuleBytesPerVoxel(LabelRule rule) {
  return sizeof(PackedVoxel) + (usesLabelSidecar(rule) ? sizeof(openvdb::Int64) : 0);
}

using LabelSidecarGrid = openvdb::Int64Grid;  // per voxel: the runners-up, 0 = none
using PackedLabelSidecar = openvdb::Int64;

// What a label update needs, precomputed once per frame by VolumeParams::labelRuleConfig() (the
// defaults are VolumeParams').
struct LabelRuleConfig {
  LabelRule rule = LabelRule::kEvidence;
  float max_score = 0.0f;                  // W_clamp
  float label_classes = 0.0f;              // L of the bayes likelihood
  float likelihood = 0.0f;                 // p_max: probability that a full-confidence pixel label is right
  float full_confidence_log_ratio = 0.0f;  // bayes evidence of one observation at w = 1 (the unit)
  // bayesIncrement at confidences k / kBayesTableSteps (tabulateBayesIncrements), which the
  // integrator interpolates instead of taking a logarithm per voxel; null: computed exactly.
  std::shared_ptr<const std::vector<float>> bayes_increments;
};

// The chance-corrected log-likelihood ratio of the bayes rule for confidence w (0 at w = 0).
inline float bayesLogRatio(float w, float label_classes, float likelihood) {
  const float chance = 1.0f / label_classes;
  const float p = chance + (likelihood - chance) * std::clamp(w, 0.0f, 1.0f);
  return std::log(p / (1.0f - p) * (label_classes - 1.0f));
}

// The top-5 list of the majority and bayes rules, leader first; label 0 = empty slot.
inline constexpr int kLabelCandidates = 5;
inline constexpr LabelId kMaxRunnerUpLabel = 1023;  // 10 bits of a sidecar slot
inline constexpr uint32_t kMaxRunnerUpQuanta = 63;  // 6 bits of a sidecar slot
struct LabelCandidates {
  LabelId label[kLabelCandidates] = {kUnlabeled, kUnlabeled, kUnlabeled, kUnlabeled, kUnlabeled};
  float score[kLabelCandidates] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
};

// Fixed-point steps of a runner-up's score per unit of evidence for a clamp of max_score: the
// most that keep 63 steps >= max_score while one unit stays a whole number of steps (3 at the
// default 16; 1 up to 63), else a fraction (one step = ceil(max_score / 63) units).
inline float runnerUpQuantaPerUnit(float max_score) {
  if (max_score <= static_cast<float>(kMaxRunnerUpQuanta))
    return std::floor(static_cast<float>(kMaxRunnerUpQuanta) / max_score);
  return 1.0f / std::ceil(max_score / static_cast<float>(kMaxRunnerUpQuanta));
}

inline LabelCandidates unpackCandidates(LabelId leader, float leader_score, PackedLabelSidecar sidecar,
                                        float quanta_per_unit) {
  const auto bits = static_cast<uint64_t>(sidecar);
  LabelCandidates c;
  c.label[0] = leader;
  c.score[0] = leader == kUnlabeled ? 0.0f : leader_score;
  for (int i = 1; i < kLabelCandidates; ++i) {
    const auto slot = static_cast<uint32_t>(bits >> (16 * (i - 1))) & 0xFFFFu;
    c.label[i] = static_cast<LabelId>(slot & kMaxRunnerUpLabel);
    c.score[i] = c.label[i] == kUnlabeled ? 0.0f : static_cast<float>(slot >> 10) / quanta_per_unit;
  }
  return c;
}

// Packs the runners-up (the leader lives in the packed voxel). Scores round to the nearest step;
// a tracked label keeps at least one step, so a small weighted vote is not lost on packing.
inline PackedLabelSidecar packSidecar(const LabelCandidates& c, float quanta_per_unit) {
  uint64_t bits = 0;
  for (int i = 1; i < kLabelCandidates; ++i) {
    if (c.label[i] == kUnlabeled) continue;
    const float steps = std::nearbyint(c.score[i] * quanta_per_unit);
    const auto quanta = static_cast<uint32_t>(std::clamp(steps, 1.0f, static_cast<float>(kMaxRunnerUpQuanta)));
    bits |= uint64_t{(quanta << 10) | (c.label[i] & kMaxRunnerUpLabel)} << (16 * (i - 1));
  }
  return static_cast<PackedLabelSidecar>(bits);
}

// Adds `increment` (> 0) of evidence for `observed` to the top-5 list (see the header comment).
inline void accumulateTopLabels(LabelCandidates& c, LabelId observed, float increment, float max_score) {
  int slot = -1, empty = -1;
  float weakest = c.score[0];
  for (int i = 0; i < kLabelCandidates; ++i) {
    if (c.label[i] == observed) slot = i;
    if (c.label[i] == kUnlabeled && empty < 0) empty = i;
    weakest = std::min(weakest, c.score[i]);
  }
  if (slot >= 0) {
    c.score[slot] += increment;
  } else if (empty >= 0) {
    c.label[empty] = observed;
    c.score[empty] = increment;
  } else {
    const float taken = std::min(increment, weakest);  // from every entry
    float left = increment - taken;
    for (int i = 0; i < kLabelCandidates; ++i) {
      c.score[i] -= taken;
      if (c.score[i] > 0.0f) continue;
      c.label[i] = left > 0.0f ? observed : kUnlabeled;  // the first used-up entry takes what is left
      c.score[i] = left > 0.0f ? left : 0.0f;
      left = 0.0f;
    }
  }
  const float top = *std::max_element(c.score, c.score + kLabelCandidates);
  if (top > max_score) {
    for (int i = 0; i < kLabelCandidates; ++i) {
      c.score[i] -= top - max_score;
      if (c.score[i] <= 0.0f) c.label[i] = kUnlabeled, c.score[i] = 0.0f;
    }
  }
  // Leader first; a stable insertion sort keeps the incumbent on ties.
  for (int i = 1; i < kLabelCandidates; ++i)
    for (int j = i; j > 0 && c.score[j] > c.score[j - 1]; --j) {
      std::swap(c.score[j], c.score[j - 1]);
      std::swap(c.label[j], c.label[j - 1]);
    }
}

// Evidence of one observation with confidence w under the bayes rule, relative to one at w = 1.
inline float bayesIncrement(float w, const LabelRuleConfig& config) {
  return bayesLogRatio(w, config.label_classes, config.likelihood) / config.full_confidence_log_ratio;
}

// Confidence steps of the bayes table: linear interpolation between them is within 1e-5 of
// bayesIncrement everywhere (tests/volume/label_rules_test.cpp), far below the half-float step
// of a stored score (1/64 at 16).
inline constexpr int kBayesTableSteps = 1024;

// The table of LabelRuleConfig::bayes_increments for this configuration.
inline std::shared_ptr<const std::vector<float>> tabulateBayesIncrements(const LabelRuleConfig& config) {
  auto table = std::make_shared<std::vector<float>>(kBayesTableSteps + 1);
  for (int k = 0; k <= kBayesTableSteps; ++k)
    (*table)[static_cast<std::size_t>(k)] = bayesIncrement(static_cast<float>(k) / kBayesTableSteps, config);
  return table;
}

// bayesIncrement from the config's table where it has one.
inline float bayesIncrementFast(float w, const LabelRuleConfig& config) {
  if (!config.bayes_increments || !(w > 0.0f)) return bayesIncrement(w, config);
  const float* table = config.bayes_increments->data();
  const float x = std::min(w, 1.0f) * static_cast<float>(kBayesTableSteps);
  const int step = static_cast<int>(x);
  if (step >= kBayesTableSteps) return table[kBayesTableSteps];
  return table[step] + (x - static_cast<float>(step)) * (table[step + 1] - table[step]);
}

// The top-5 rules' update with `increment` (> 0) of evidence for `observed`, through the whole
// candidate list: unpack, accumulateTopLabels, pack. Kept out of line so that the common case in
// applyLabelRule stays small enough to inline into the integrator's loop.
[[gnu::noinline]] inline void applyTopLabels(const LabelRuleConfig& config, LabelId& label, float& score,
                                             PackedLabelSidecar* sidecar, LabelId observed, float increment) {
  const float quanta_per_unit = runnerUpQuantaPerUnit(config.max_score);
  LabelCandidates c = unpackCandidates(label, score, *sidecar, quanta_per_unit);
  accumulateTopLabels(c, observed, increment, config.max_score);
  label = c.label[0];
  score = c.score[0];
  *sidecar = packSidecar(c, quanta_per_unit);
}

// The per-voxel update of every rule, called by the integrator where a frame's label reaches a
// voxel. `sidecar` points at the voxel's sidecar value (unused, may be null, for evidence).
inline void applyLabelRule(const LabelRuleConfig& config, LabelId& label, float& score, PackedLabelSidecar* sidecar,
                           LabelId observed, float w) {
  if (config.rule == LabelRule::kEvidence) {
    fuseLabelEvidence(label, score, observed, w, config.max_score);
    return;
  }
  if (observed > kMaxRunnerUpLabel) return;  // cannot be a runner-up: outside the rule's legends
  const float increment = config.rule == LabelRule::kMajority ? 1.0f : bayesIncrementFast(w, config);
  if (!(increment > 0.0f)) return;
  // Most updates meet a voxel with no runner-up that sees its leader again, or its first label:
  // the list's result is then the leader's score plus the increment, clamped, and an empty
  // sidecar. The same arithmetic as accumulateTopLabels (`top - (top - clamp)`, not `clamp`), so
  // the bits are the same whichever way a voxel goes.
  if (*sidecar == 0 && (label == kUnlabeled || (label == observed && score >= 0.0f))) {
    const float top = label == kUnlabeled ? increment : score + increment;
    score = top > config.max_score ? top - (top - config.max_score) : top;
    label = observed;
    return;
  }
  applyTopLabels(config, label, score, sidecar, observed, increment);
}

}  // namespace semfuse::volume
