#pragma once
// A recorded RGB-D sequence with reference poses, decoded into memory once so that every
// tracking case replays it without decoding inside the timed loop.
//   tum:DIR          a TUM RGB-D folder (depth, colour and motion-capture ground truth associated
//                    by time stamp; the ground truth interpolated to each depth stamp)
//   7scenes:DIR      a 7-Scenes folder (reference poses from the dataset's KinectFusion run)
//   synthetic[:N]    the built-in synthetic room, N frames of its orbit (exact poses)
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::bench {

class TrackSequence {
 public:
  // Loads at most max_frames frames (0 = all), decoding in parallel.
  static Result<TrackSequence> load(const std::string& spec, std::size_t max_frames);

  const std::string& name() const { return name_; }
  // What the reference poses are: "motion capture", "KinectFusion reconstruction", "exact".
  const std::string& referenceKind() const { return reference_kind_; }
  // True where the reference is independent of depth alignment (motion capture, exact poses):
  // then integrated poses are judged against it; otherwise against an unbroken tracked run.
  bool referenceIsTruth() const { return reference_is_truth_; }
  // False where the colour image is not registered to the depth image (7-Scenes): the photometric
  // term would pull poses towards the colour camera's view, so such a sequence is tracked on
  // depth alone, as the server does with --track-color-weight 0.
  bool colorRegistered() const { return color_registered_; }
  std::size_t size() const { return frames_.size(); }
  // Frame i without its pose (the tracker must find it); colour when the sequence has it.
  const Frame& frame(std::size_t i) const { return frames_[i]; }
  // The reference pose of frame i; none where the reference has a gap (motion capture drop-outs).
  const std::optional<Pose>& reference(std::size_t i) const { return references_[i]; }

 private:
  std::string name_;
  std::string reference_kind_;
  bool reference_is_truth_ = false;
  bool color_registered_ = true;
  std::vector<Frame> frames_;
  std::vector<std::optional<Pose>> references_;
};

}  // namespace semfuse::bench
