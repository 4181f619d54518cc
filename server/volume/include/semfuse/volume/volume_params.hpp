#pragma once
// Parameters of a labeled volume. A plain struct so that config files, the server and tests can
// fill it directly; validate() says precisely what is wrong before a volume is built from it.
// The member initializers are the defaults everywhere (the server's flags, map files); every field
// has a row in volume_param_table.hpp, which is where its flag, range and map file key live.
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/volume/label_rules.hpp"

namespace semfuse::volume {

struct VolumeParams {
  double voxel_size = 0.01;  // metres, edge of one voxel
  double truncation = 0.04;  // metres; the TSDF is clamped to [-truncation, +truncation]

  // Integration weights are stored as half floats, which hold every integer up to 2048 exactly,
  // so the running average stays exact up to that clamp.
  float max_weight = 64.0f;
  // Where behind the surface an observation's weight starts to fall, as a fraction of the
  // truncation: 1 in front of the surface and down to this depth behind it, then linearly less,
  // to 1/16 at -truncation (the linear weight of Bylow et al. 2013). A pixel says little about
  // what lies well behind the surface it saw: the far side of a thin object or an edge should not
  // outweigh the views that see that side. It starts this deep because the truncation is a few
  // times the depth noise, and a drop within the noise would weigh the noisy samples in front of a
  // surface above those behind it. 1: every observation weighs 1 (KinectFusion's, vdbfusion's and
  // voxblox's constant weight).
  float weight_dropoff = 0.75f;

  // W_clamp of Algorithm 1: the most evidence a voxel's label can accumulate. With confidences
  // around 0.5-1 a label saturates after ~16-32 agreeing frames (about one second at 30 Hz), and a
  // saturated but wrong label is overturned by about as long a run of contrary evidence. A much
  // larger clamp makes early mistakes permanent; a smaller one lets single noisy frames flip labels.
  // 16 also keeps the half-float score's resolution (1/128 near the clamp) below typical increments.
  float max_label_score = 16.0f;

  // How labels are fused (label_rules.hpp). bayes fused the least volumetric error in docs/eval;
  // evidence is the paper's rule and keeps no sidecar (the top-5 rules cost a sidecar grid of 8
  // more bytes per voxel), so geometry-only volumes choose it. max_label_score is every rule's
  // W_clamp (in full-confidence observations for majority and bayes).
  LabelRule label_rule = LabelRule::kBayes;
  // The bayes rule's likelihood: a full-confidence pixel label is right with probability
  // label_likelihood (Kimera-Semantics uses 0.9), a wrong one is any of label_classes - 1 others.
  float label_likelihood = 0.9f;
  int label_classes = 20;

  float min_depth = 0.1f;  // metres; depth outside [min_depth, max_depth] is ignored
  float max_depth = 5.0f;

  // Labels that never change a voxel (as label 0 = unlabeled never does), e.g. "other" classes.
  std::vector<LabelId> background_labels;

  bool integrate_color = true;  // keep a colour grid (4 bytes per voxel extra)

  Status validate() const;
  LabelRuleConfig labelRuleConfig() const;
};

}  // namespace semfuse::volume
