#pragma once
// The synthetic room as a camera would stream it: frame i is a semfuse::Frame (depth, colour,
// intrinsics, pose) plus the ground-truth Segmentation a perfect segmenter would publish.
#include <cstdint>
#include <optional>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/synthetic/depth_noise.hpp"
#include "semfuse/synthetic/labeled_scene.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"

namespace semfuse::synthetic {

struct SequenceConfig {
  RoomOptions room;
  OrbitTrajectory trajectory;
  // Kinect-like defaults: 640x480, 525 px focal length.
  PinholeIntrinsics intrinsics{640, 480, 525.0, 525.0, 319.5, 239.5};
  std::optional<DepthNoiseParams> noise;  // none: exact depth
  uint64_t seed = 0;                      // noise; textures use room.seed
  double frame_rate_hz = 30.0;
  std::string camera_id = "synthetic";
  std::string segmenter_id = "ground-truth";
  // The ground truth is panoptic: it carries each pixel's object instance (the room's own ids).
  bool instances = false;
};

class SyntheticSequence {
 public:
  explicit SyntheticSequence(SequenceConfig config = {});

  int frameCount() const { return config_.trajectory.frame_count; }
  const SequenceConfig& config() const { return config_; }
  const LabeledScene& scene() const { return scene_; }
  Pose pose(int index) const { return config_.trajectory.pose(index); }

  // Exact rendering of frame `index` (no noise). Fails for an index outside [0, frameCount()).
  Result<RenderedView> view(int index) const;
  // Frame `index`: depth (noisy if configured), colour, intrinsics, stamp, seq = index, and the
  // true camera_to_world pose when with_pose (a tracker test drops it).
  Result<Frame> frame(int index, bool with_pose = true) const;
  // Ground-truth labels of frame `index` with confidence 1 wherever a label is present, and the
  // instance map when the config asks for it.
  Result<Segmentation> groundTruth(int index) const;
  // Both from one rendering (rendering dominates the cost).
  Result<std::pair<Frame, Segmentation>> frameWithGroundTruth(int index, bool with_pose = true) const;

 private:
  Status checkIndex(int index) const;
  Frame makeFrame(const RenderedView& view, int index, bool with_pose) const;
  Segmentation makeSegmentation(const RenderedView& view, int index) const;
  Stamp stampOf(int index) const;

  SequenceConfig config_;
  LabeledScene scene_;
};

}  // namespace semfuse::synthetic
