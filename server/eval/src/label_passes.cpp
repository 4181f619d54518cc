#include "label_passes.hpp"

#include <chrono>
#include <ctime>

#include "semfuse/segmentation/noise_model.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::eval {
namespace {

// Confidence the simulated CNN gives to regions it keeps / switches: real networks are less sure
// where they are wrong, but not nearly unsure enough to be ignored.
constexpr float kCnnKeptConfidence = 0.9f;
constexpr float kCnnSwitchedConfidence = 0.55f;

std::string referenceKey(const volume::VolumeParams& p) {
  return std::string(volume::labelRuleName(p.label_rule)) + "/" + std::to_string(p.max_label_score) + "/" +
         std::to_string(p.label_likelihood) + "/" + std::to_string(p.label_classes);
}

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

}  // namespace

const char* weightModeName(WeightMode mode) {
  switch (mode) {
    case WeightMode::kConfidence:
      return "confidence";
    case WeightMode::kConstant:
      return "constant";
    case WeightMode::kSquared:
      return "squared";
  }
  return "unknown";
}

Result<Segmentation> labelsFor(const EvalSequence& sequence, std::size_t i, const LabelSource& source) {
  if (i >= sequence.frames.size()) return makeError("frame " + std::to_string(i) + " out of range");
  Segmentation clean;
  clean.frame_seq = i;
  if (source.kind == LabelSourceKind::kSegmenter) {
    if (i >= sequence.segmentations.size()) return makeError(sequence.name + " has no segmenter output");
    clean = sequence.segmentations[i];
    if (clean.labels.empty()) return clean;  // the network did not run on this frame
  } else {
    clean.labels = sequence.truth[i];
    clean.confidence = cv::Mat(clean.labels.size(), CV_32FC1, cv::Scalar(1.0f));
  }
  Segmentation result = clean;
  if (source.kind == LabelSourceKind::kPixel || source.kind == LabelSourceKind::kRegion ||
      source.kind == LabelSourceKind::kSimulatedCnn) {
    segmentation::NoiseParams noise;
    noise.model =
        source.kind == LabelSourceKind::kPixel ? segmentation::NoiseModel::kPixel : segmentation::NoiseModel::kRegion;
    noise.probability = source.probability;
    noise.seed = source.seed;
    noise.candidates = sequence.present_labels;
    auto noisy = segmentation::addLabelNoise(clean, noise, i);
    if (!noisy) return makeError(noisy.error());
    result = std::move(noisy).value();
    if (source.kind == LabelSourceKind::kSimulatedCnn) {
      result.confidence = cv::Mat(clean.labels.size(), CV_32FC1, cv::Scalar(kCnnKeptConfidence));
      result.confidence.setTo(kCnnSwitchedConfidence, result.labels != clean.labels);
    }
  }
  if (source.weight == WeightMode::kConstant) result.confidence.setTo(1.0f);
  else if (source.weight == WeightMode::kSquared) result.confidence = result.confidence.mul(result.confidence);
  return result;
}

volume::LabeledVolume withLabelRule(const volume::LabeledVolume& geometry, const volume::VolumeParams& params) {
  volume::LabeledVolume copy(params);
  copy.mutableGeometryGrid().setTree(std::make_shared<volume::GeometryGrid::TreeType>(geometry.geometryGrid().tree()));
  copy.setFramesIntegrated(geometry.framesIntegrated());
  return copy;  // integrateLabels allocates the sidecar leaves beside the geometry's on first use
}

Result<PassCost> fuseLabels(volume::LabeledVolume& volume, const EvalSequence& sequence, const LabelSource& source) {
  PassCost cost;
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = cpuSeconds();
  for (std::size_t i = 0; i < sequence.frames.size(); ++i) {
    auto labels = labelsFor(sequence, i, source);
    if (!labels) return makeError(labels.error());
    if (labels.value().labels.empty()) continue;  // no segmentation of this frame
    const EvalFrame& frame = sequence.frames[i];
    auto stats = volume::integrateLabels(volume, frame.depth, labels.value().labels, labels.value().confidence,
                                         sequence.intrinsics, frame.camera_to_world);
    if (!stats) return makeError(sequence.name + " frame " + std::to_string(i) + ": " + stats.error());
    ++cost.frames;
  }
  cost.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  cost.cpu_s = cpuSeconds() - cpu_start;
  return cost;
}

Scenario::Scenario(const EvalSequence& sequence, volume::LabeledVolume geometry)
    : sequence_(&sequence), geometry_(std::move(geometry)), surface_(surfaceVoxels(geometry_)) {}

Result<const volume::LabeledVolume*> Scenario::reference(const volume::VolumeParams& params) {
  const std::string key = referenceKey(params);
  auto found = references_.find(key);
  if (found == references_.end()) {
    volume::LabeledVolume fused = withLabelRule(geometry_, params);
    auto cost = fuseLabels(fused, *sequence_, LabelSource{});
    if (!cost) return makeError(cost.error());
    found = references_.emplace(key, std::move(fused)).first;
  }
  return &found->second;
}

Result<Scenario::Outcome> Scenario::run(const volume::VolumeParams& params, const LabelSource& source) {
  auto ref = reference(params);
  if (!ref) return makeError(ref.error());
  return run(params, source, *ref.value());
}

Result<Scenario::Outcome> Scenario::run(const volume::VolumeParams& params, const LabelSource& source,
                                        const volume::LabeledVolume& reference) {
  volume::LabeledVolume fused = withLabelRule(geometry_, params);
  auto cost = fuseLabels(fused, *sequence_, source);
  if (!cost) return makeError(cost.error());
  Outcome outcome;
  outcome.cost = cost.value();
  outcome.error = volumetricLabelError(reference, fused, surface_);
  if (fused.allocatedVoxels() > 0)
    outcome.sidecar_bytes_per_voxel =
        static_cast<double>(fused.labelSidecarMemoryBytes()) / static_cast<double>(fused.allocatedVoxels());
  return outcome;
}

}  // namespace semfuse::eval
