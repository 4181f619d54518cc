#pragma once
// Finding a lost camera from far away: the keyframes' ORB keypoints (Rublee et al., ICCV 2011),
// placed in the world by their depth, are matched one by one to a lost frame's keypoints, and a
// pose that projects enough of the matched points onto their pixels (PnP inside RANSAC) proposes
// where the camera is. The keyframe store's ferns compare whole small images, so they find a
// camera only near a keyframe's viewpoint; single keypoints are matched across the changes of
// scale and perspective of a camera a metre or 30 degrees away from every keyframe.
// A proposal is only a start: the SDF alignment and the tracker's tests decide whether it holds.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "semfuse/core/types.hpp"

namespace semfuse::tracking {

struct KeypointParams {
  int features = 1000;   // ORB keypoints per image
  int max_hamming = 64;  // of 256 bits: descriptors further apart do not match
  float ratio = 0.8f;    // nearest over second-nearest distance in one keyframe (Lowe's test)
  // The keyframes with the most matches (at least min_matches / 2 each), whose points together PnP
  // explains.
  std::size_t keyframes_tried = 5;
  int min_matches = 12;          // matches before PnP is tried
  int min_inliers = 12;          // matches a proposed pose must explain
  double reprojection_px = 6.0;  // RANSAC's inlier threshold, for a 640 px wide image
  int ransac_iterations = 300;
  // A lost frame compares its descriptors with at most this many stored ones (about 30 ms on two
  // cores, some 50 keyframes); a larger map is searched in turns over the next frames.
  std::size_t max_compared = 40000;
};

// One image's keypoints that have a depth.
struct FrameKeypoints {
  std::vector<cv::Point2f> pixels;
  std::vector<Eigen::Vector3f> points;  // in the camera frame, metres
  cv::Mat descriptors;                  // CV_8UC1, a 32-byte row per keypoint
  std::size_t size() const { return pixels.size(); }
  bool empty() const { return pixels.empty(); }
};

struct KeypointPose {
  Pose camera_to_world = Pose::Identity();
  std::size_t keyframe = 0;  // the keyframe with most votes among those whose points it explains
  int matches = 0;           // matched to those keyframes' points
  int inliers = 0;           // of them, explained by the pose
};

// Keypoints of a frame matched to world points of the keyframes.
struct KeypointMatches {
  std::vector<cv::Point3f> world;
  std::vector<cv::Point2f> pixels;  // the frame's, one per world point
  // How many of them a pose projects within max_px of their pixel.
  int explainedBy(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics, double max_px) const;
};

class KeypointMap {
 public:
  explicit KeypointMap(KeypointParams params = {});

  // The ORB keypoints of a frame's colour (CV_8UC3 RGB) that have a depth (CV_32FC1 metres) on a
  // surface, not on a depth edge. Empty without colour.
  // Safe to call from several threads at once.
  FrameKeypoints detect(const cv::Mat& color, const cv::Mat& depth, const PinholeIntrinsics& intrinsics) const;

  // Remembers a keyframe's keypoints at its pose.
  void add(const FrameKeypoints& keypoints, const Pose& camera_to_world);

  // A pose that explains the frame's keypoints by those of the keyframes that share most of them.
  std::optional<KeypointPose> locate(const FrameKeypoints& frame, const PinholeIntrinsics& intrinsics);

  // Of the matches the last locate() tried, how many a pose projects within max_px of their pixel:
  // evidence for a pose found by other means that does not depend on the depth.
  int explained(const Pose& camera_to_world, const PinholeIntrinsics& intrinsics, double max_px) const {
    return last_.explainedBy(camera_to_world, intrinsics, max_px);
  }
  // Those matches, to judge a pose by after the map has moved on to another search.
  const KeypointMatches& lastMatches() const { return last_; }

  std::size_t keyframes() const { return keyframes_.size(); }
  std::size_t descriptors() const { return static_cast<std::size_t>(all_descriptors_.rows); }
  void clear();

 private:
  struct StoredKeyframe {
    int first_row = 0;  // its descriptors: rows first_row.. of all_descriptors_, one per world point
    std::vector<cv::Point3f> world_points;
  };
  // Matches of the frame to each keyframe, counted over this turn's share of the stored descriptors.
  std::vector<int> vote(const FrameKeypoints& frame);
  bool solve(const FrameKeypoints& frame, const PinholeIntrinsics& intrinsics,
             const std::vector<std::size_t>& keyframes, KeypointPose& out);

  KeypointParams params_;
  std::vector<StoredKeyframe> keyframes_;
  cv::Mat all_descriptors_;      // every keyframe's descriptors, one after another
  std::vector<uint32_t> owner_;  // the keyframe of each row of all_descriptors_
  std::size_t next_row_ = 0;     // where the next turn of a large map's search starts
  KeypointMatches last_;         // the matches the last locate() tried
};

}  // namespace semfuse::tracking
