#pragma once
// Label fusion rules: how a voxel's label changes when a frame observes it with label `observed`
// and confidence `w`. Every rule leaves its winner in the packed voxel's label/score, so raycast,
// mesh, queries and map files read every rule the same way.
//
//  evidence  Algorithm 1 of Cavallari & Di Stefano (label_fusion.hpp): one label, one score;
//            8 bytes per voxel with geometry.
//  majority  a count of the observations of each of the voxel's top-3 labels (confidence ignored).
//  bayes     the log-probability of each of the top-3 labels under a calibrated likelihood
//            (Kimera-Semantics style): a pixel with confidence c is right with probability
//            p(c) = 1/L + (p_max - 1/L) * c and otherwise any of the L-1 other labels, so the
//            observed label gains log(p(c) (L-1) / (1 - p(c))) over every other label. Scores are in
//            units of one full-confidence observation (a positive scale changes no decision).
//
// The two top-3 rules keep the leader in the packed voxel and the two runners-up in a sidecar
// grid of the same topology (64 bits: label, half score, label, half score): 16 bytes per voxel.
// Truncation to 3 labels is the weighted Misra-Gries summary: a label outside a full list takes
// the same amount of evidence from every entry (at most the weakest entry's) and enters with what
// is left once an entry is used up. Eroding only the weakest entry instead lets two early wrong
// labels hold their slots for good while the true label churns in the third (measured: a fifth of
// the voxels stuck at 70% pixel noise); eroding all of them lets every label with more than a
// quarter of the evidence reach the list. The clamp W_clamp bounds the leader's lead over the untracked labels: when a score would
// pass it, all scores shift down (a log-probability is defined up to a constant), which keeps the
// differences, i.e. the decision, and lets a changed scene be relearned in about W_clamp frames.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

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

// What a label update needs, precomputed once per frame.
struct LabelRuleConfig {
  LabelRule rule = LabelRule::kEvidence;
  float max_score = 16.0f;   // W_clamp
  float label_classes = 20;  // L of the bayes likelihood
  float likelihood = 0.9f;   // p_max: probability that a full-confidence pixel label is right
  float full_confidence_log_ratio = 1.0f;  // bayes evidence of one observation at w = 1 (the unit)
};

// The chance-corrected log-likelihood ratio of the bayes rule for confidence w (0 at w = 0).
inline float bayesLogRatio(float w, float label_classes, float likelihood) {
  const float chance = 1.0f / label_classes;
  const float p = chance + (likelihood - chance) * std::clamp(w, 0.0f, 1.0f);
  return std::log(p / (1.0f - p) * (label_classes - 1.0f));
}

// The top-3 list of the majority and bayes rules, leader first; label 0 = empty slot.
inline constexpr int kLabelCandidates = 3;
struct LabelCandidates {
  LabelId label[kLabelCandidates] = {kUnlabeled, kUnlabeled, kUnlabeled};
  float score[kLabelCandidates] = {0.0f, 0.0f, 0.0f};
};

inline LabelCandidates unpackCandidates(LabelId leader, float leader_score, PackedLabelSidecar sidecar) {
  const auto bits = static_cast<uint64_t>(sidecar);
  LabelCandidates c;
  c.label[0] = leader;
  c.score[0] = leader == kUnlabeled ? 0.0f : leader_score;
  for (int i = 1; i < kLabelCandidates; ++i) {
    const uint64_t slot = bits >> (32 * (i - 1));
    c.label[i] = static_cast<LabelId>(slot & 0xFFFFu);
    c.score[i] = c.label[i] == kUnlabeled ? 0.0f : detail::halfValue(slot >> 16);
  }
  return c;
}

inline PackedLabelSidecar packSidecar(const LabelCandidates& c) {
  uint64_t bits = 0;
  for (int i = 1; i < kLabelCandidates; ++i) {
    const uint64_t slot = uint64_t{c.label[i]} | (uint64_t{detail::halfBits(c.score[i])} << 16);
    bits |= slot << (32 * (i - 1));
  }
  return static_cast<PackedLabelSidecar>(bits);
}

// Adds `increment` (> 0) of evidence for `observed` to the top-3 list (see the header comment).
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

// The per-voxel update of every rule, called by the integrator where a frame's label reaches a
// voxel. `sidecar` points at the voxel's sidecar value (unused, may be null, for evidence).
inline void applyLabelRule(const LabelRuleConfig& config, LabelId& label, float& score, PackedLabelSidecar* sidecar,
                           LabelId observed, float w) {
  if (config.rule == LabelRule::kEvidence) {
    fuseLabelEvidence(label, score, observed, w, config.max_score);
    return;
  }
  LabelCandidates c = unpackCandidates(label, score, *sidecar);
  const float increment = config.rule == LabelRule::kMajority ? 1.0f : bayesIncrement(w, config);
  if (increment > 0.0f) accumulateTopLabels(c, observed, increment, config.max_score);
  label = c.label[0];
  score = c.score[0];
  *sidecar = packSidecar(c);
}

}  // namespace semfuse::volume
