#pragma once
// Algorithm 1 of Cavallari & Di Stefano (PSIVT 2015): how one voxel's label and score change when
// a frame observes it with label `observed` and confidence `w`. Callers have already excluded
// label 0 (unlabeled) and background labels, which change nothing, and checked that the frame's
// depth agrees with the voxel. Kept as a pure function so every branch is tested on its own.
#include <algorithm>

#include "semfuse/core/legend.hpp"

namespace semfuse::volume {

inline void fuseLabelEvidence(LabelId& label, float& score, LabelId observed, float w, float max_score) {
  if (label == kUnlabeled || score < 0.0f) {
    label = observed;  // nothing known yet, or the old label has been outvoted: take the new one
    score = w;
  } else if (label == observed) {
    score = std::min(score + w, max_score);  // agreement builds evidence up to W_clamp
  } else {
    score -= w;  // disagreement erodes it; the label is replaced once the score goes negative
  }
}

}  // namespace semfuse::volume
