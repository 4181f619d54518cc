#pragma once
// Synthetic segmentation errors, to study how label fusion copes with a bad segmenter.
//  pixel model (the paper's): each labeled pixel is switched, with probability p, to a wrong
//    label drawn uniformly from the candidate labels, with maximum confidence (the worst case:
//    the error is as sure of itself as a correct label).
//  region model: each connected region of one label is switched as a whole, with probability p,
//    to one wrong label: errors that are spatially coherent, like a real network's.
// Unlabeled pixels (0) stay unlabeled. A panoptic segmentation's instance map, when there is one,
// gets its ids renumbered at random (a segmenter's ids name nothing beyond its frame) and every
// instance mask eroded by instance_erosion pixels (borders that lose their instance, as a
// network's masks do at object edges). Deterministic: the same input, seed and frame seq give
// the same output, and different frames get independent noise.
#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::segmentation {

enum class NoiseModel { kPixel, kRegion };

struct NoiseParams {
  NoiseModel model = NoiseModel::kPixel;
  double probability = 0.3;
  uint64_t seed = 0;
  std::vector<LabelId> candidates;  // the wrong labels to draw from; needs at least two ids
  int instance_erosion = 0;         // pixels taken off every instance mask's border
};

Result<NoiseModel> parseNoiseModel(const std::string& text);

// Corrupts clean.labels (CV_16UC1) as described above; the confidence of a switched pixel
// becomes 1, others keep theirs (1 where clean has none).
Result<Segmentation> addLabelNoise(const Segmentation& clean, const NoiseParams& params, uint64_t frame_seq);

}  // namespace semfuse::segmentation
