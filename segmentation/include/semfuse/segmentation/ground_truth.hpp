#pragma once
// Ground-truth segmenters: what a perfect segmenter would say.
//  SyntheticGroundTruth re-renders the built-in synthetic room's labels at the frame's own pose
//    and intrinsics (so frames must carry poses: semfuse-camera without --no-poses).
//  LabelFolder reads a label image per frame from a folder, for datasets that ship them.
#include <filesystem>
#include <string>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/synthetic/labeled_scene.hpp"

namespace semfuse::segmentation {

class SyntheticGroundTruth {
 public:
  // with_instances: also the room's exact instance map (a panoptic segmenter's output).
  explicit SyntheticGroundTruth(bool with_instances = false);
  // Labels where the room is hit, 0 elsewhere; confidence 1; instances when asked for.
  Result<Segmentation> segment(const Frame& frame) const;

 private:
  synthetic::LabeledScene scene_;
  bool with_instances_;
};

class LabelFolder {
 public:
  // pattern: file name with one {} for the frame's seq, fmt-style, e.g. "frame-{:06d}.label.png".
  LabelFolder(std::filesystem::path folder, std::string pattern);
  // The 16-bit (or 8-bit) PNG of the frame's seq; confidence 1.
  Result<Segmentation> segment(const Frame& frame) const;
  std::filesystem::path fileFor(uint64_t seq) const;

 private:
  std::filesystem::path folder_;
  std::string pattern_;
};

}  // namespace semfuse::segmentation
