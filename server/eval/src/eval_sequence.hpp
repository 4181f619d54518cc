#pragma once
// The sequences the experiments run on, loaded once: depth and pose of every frame (geometry is
// integrated once per sequence) and the per-frame "true" labels the noise models corrupt.
//  synthetic: the built-in room on an orbit, exact labels from the renderer, Kinect-like depth
//    noise; rendered frames are cached on disk (depth TIFF, labels PNG).
//  7scenes: redkitchen depth with its reference poses; the true labels are the raycast of a
//    reference labeling (the ADE20K DeepLab-513 labels fused over the frames the networks run on)
//    into each frame, and `segmentations` holds the DeepLab-257 output (the real segmenter of
//    experiment 3). The networks run on every network_stride-th frame only (they dominate the
//    cost); truth comes from the raycast, so label passes can use more frames than that.
//    Network outputs are cached on disk (labels PNG, confidence 16-bit PNG).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::eval {

struct EvalFrame {
  cv::Mat depth;  // CV_32FC1 metres
  Pose camera_to_world = Pose::Identity();
};

struct EvalSequence {
  std::string name;
  PinholeIntrinsics intrinsics;
  std::vector<EvalFrame> frames;
  std::vector<cv::Mat> truth;               // CV_16UC1 per frame, 0 = unlabeled
  std::vector<cv::Mat> instances;           // CV_16UC1 per frame, the true object instance (synthetic only)
  std::vector<Segmentation> segmentations;  // a real segmenter's output per frame (7scenes only;
                                            // empty labels where it did not run)
  std::vector<LabelId> present_labels;      // labels in `truth`: the noise models' wrong labels
  // 7scenes: the fused reference labeling whose raycasts are `truth` (experiment 3 scores
  // the real segmenter against it).
  std::shared_ptr<const volume::LabeledVolume> reference_labeling;
};

struct SyntheticOptions {
  std::string name = "synthetic";
  int frames = 120;
  double scale = 0.5;      // of the 640x480 Kinect-like camera
  double phase_rad = 0.0;  // trajectory variants
  double radius = 1.6;
  double height = 1.4;
  uint64_t seed = 1;  // depth noise
};

Result<EvalSequence> loadSynthetic(const SyntheticOptions& options, const std::filesystem::path& cache);

struct SevenScenesOptions {
  std::filesystem::path folder;  // 7-Scenes sequence folder
  std::filesystem::path models;  // folder with the ADE20K DeepLab .pb files
  int frames = 500;
  int stride = 1;               // frames integrated and fused
  int network_stride = 4;       // frames the networks segment: a multiple of stride
  volume::VolumeParams params;  // geometry of the reference labeling
};

// Also returns, through `on_progress(done, total)`, progress of the slow network passes.
Result<EvalSequence> loadSevenScenes(
    const SevenScenesOptions& options, const std::filesystem::path& cache,
    const std::function<void(const std::string&, std::size_t, std::size_t)>& on_progress);

// Depth-only integration of every frame: the geometry the label passes share.
Result<volume::LabeledVolume> integrateGeometry(const EvalSequence& sequence, const volume::VolumeParams& params);

}  // namespace semfuse::eval
