#pragma once
// Label passes over a sequence whose geometry is already integrated: a copy of the geometry gets
// one label rule, then every frame's labels (true, or corrupted by a noise model) are fused with
// integrateLabels(), exactly as the server fuses late segmentations.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <openvdb/openvdb.h>

#include "eval_sequence.hpp"
#include "label_metric.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::eval {

enum class LabelSourceKind {
  kTruth,         // the sequence's true labels, confidence 1
  kPixel,         // the paper's model: pixels switched independently, full confidence
  kRegion,        // connected regions switched as a whole, full confidence
  kSimulatedCnn,  // region noise; confidence 0.9 on kept regions, 0.55 on switched ones
  kSegmenter,     // the sequence's real segmenter output
};
// What the rule receives as the pixel's weight.
enum class WeightMode { kConfidence, kConstant, kSquared };

struct LabelSource {
  LabelSourceKind kind = LabelSourceKind::kTruth;
  double probability = 0.0;
  uint64_t seed = 0;
  WeightMode weight = WeightMode::kConfidence;
};

const char* weightModeName(WeightMode mode);

// The segmentation a source gives for frame i (deterministic in source.seed and i); empty labels
// for a segmenter source on a frame the segmenter did not run on.
Result<Segmentation> labelsFor(const EvalSequence& sequence, std::size_t i, const LabelSource& source);

// A copy of the (label-free) geometry with the params' label rule and an empty sidecar.
volume::LabeledVolume withLabelRule(const volume::LabeledVolume& geometry, const volume::VolumeParams& params);

struct PassCost {
  double wall_s = 0.0;
  double cpu_s = 0.0;  // process CPU time, all threads
  std::size_t frames = 0;
};

// Fuses the source's labels of every frame into `volume`.
Result<PassCost> fuseLabels(volume::LabeledVolume& volume, const EvalSequence& sequence, const LabelSource& source);

// A sequence with its geometry, surface voxels and per-rule references (the same rule fed the
// true labels, so that every rule scores exactly 0 at p = 0), built on first use.
class Scenario {
 public:
  Scenario(const EvalSequence& sequence, volume::LabeledVolume geometry);

  const EvalSequence& sequence() const { return *sequence_; }
  const volume::LabeledVolume& geometry() const { return geometry_; }
  const std::vector<openvdb::Coord>& surface() const { return surface_; }

  struct Outcome {
    LabelError error;
    PassCost cost;
    double sidecar_bytes_per_voxel = 0.0;  // measured sidecar memory / allocated voxels
  };
  // Fuses the source with the params' rule and scores it against that rule's reference.
  Result<Outcome> run(const volume::VolumeParams& params, const LabelSource& source);
  // Scores against a given reference volume instead (experiment 3 on real data).
  Result<Outcome> run(const volume::VolumeParams& params, const LabelSource& source,
                      const volume::LabeledVolume& reference);

 private:
  Result<const volume::LabeledVolume*> reference(const volume::VolumeParams& params);

  const EvalSequence* sequence_;
  volume::LabeledVolume geometry_;
  std::vector<openvdb::Coord> surface_;
  std::map<std::string, volume::LabeledVolume> references_;
};

}  // namespace semfuse::eval
