#pragma once
// The places a map has been seen from, for finding a camera again: keyframes encoded with random
// ferns (Glocker, Shotton, Criminisi and Izadi, "Real-time RGB-D camera relocalization via
// randomized ferns for keyframe encoding", TVCG 2015). Each fern is a few binary tests on a small
// image (is the intensity or depth at this pixel above this threshold?); a frame's code is the
// outcome of every fern, and two frames that look alike share most of their fern outcomes. A
// frame that differs enough from every keyframe becomes one, so the store grows with the area
// seen, not with time. A lost camera's frame is looked up among the keyframes; the nearest ones
// propose poses, which alignment then verifies.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/core/types.hpp"
#include "semfuse/tracking/image_pyramid.hpp"

namespace semfuse::tracking {

struct KeyframeParams {
  int ferns = 500;
  int tests_per_fern = 4;  // at most 8 (a code is one byte)
  // A frame becomes a keyframe when it differs from every stored one in at least this share of
  // its fern outcomes.
  double novelty = 0.2;
  std::size_t max_keyframes = 2000;  // beyond it new places are not remembered (and it is logged)
  uint64_t seed = 0x5e3f05e5;        // the ferns' tests; fixed so that codes stay comparable
};

struct Keyframe {
  std::string camera_id;
  Pose camera_to_world = Pose::Identity();
  ImagePyramid images;  // its small images: the reference for aligning a frame to it
  std::vector<uint8_t> code;
};

struct KeyframeMatch {
  std::size_t index = 0;
  double similarity = 0.0;  // share of fern outcomes in common, 0..1
};

class KeyframeStore {
 public:
  explicit KeyframeStore(KeyframeParams params = {});

  // The fern code of a frame's images (the level of 80x60 or the nearest to it).
  std::vector<uint8_t> encode(const ImagePyramid& images) const;

  // Stores the frame as a keyframe when it is new enough; true if it was stored.
  bool addIfNovel(const std::string& camera_id, const Pose& camera_to_world, const ImagePyramid& images);

  // The stored keyframes most similar to `code`, best first, at most `count`.
  std::vector<KeyframeMatch> nearest(const std::vector<uint8_t>& code, std::size_t count) const;

  const Keyframe& keyframe(std::size_t index) const { return keyframes_[index]; }
  std::size_t size() const { return keyframes_.size(); }
  void clear();

 private:
  struct Test {
    int level;   // the image level the tests read
    int x, y;    // pixel
    bool depth;  // depth (metres) or intensity (0..1)
    float threshold;
  };
  // Share of equal outcomes with every keyframe, through the inverted lists.
  std::vector<int> agreementCounts(const std::vector<uint8_t>& code) const;

  KeyframeParams params_;
  std::vector<Test> tests_;  // ferns x tests_per_fern
  std::vector<Keyframe> keyframes_;
  // For each fern and each of its outcomes, the keyframes that have it.
  std::vector<std::vector<std::vector<uint32_t>>> inverted_;
};

}  // namespace semfuse::tracking
