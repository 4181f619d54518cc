#pragma once
// Which frames saw which part of the map: for the objects' "frames that saw it".
//
// For every fused frame, the depth of every 8th pixel of every 8th row is lifted into the world;
// each map leaf (8^3 voxels) such a point lands in remembers the frame, up to the latest
// frames_per_leaf frames per leaf. A frame saw an object when it saw one of the object's leaves;
// frames that saw more of its leaves come first. The depth is what the frame saw, so a frame that
// looked at an occluded object does not count. Thread-safe: the fusion thread records while query
// threads ask. Kept in memory only: after a restart or a map load it knows the frames fused since.
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/service_types.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::objects {

class ViewIndex {
 public:
  static constexpr std::size_t kFramesPerLeaf = 16;
  static constexpr std::size_t kMaxFrames = 1u << 16;  // frames remembered; older ones are forgotten

  explicit ViewIndex(double voxel_size) : voxel_size_(voxel_size) {}

  // depth: CV_32FC1 metres; pixels outside [min_depth, max_depth] (or not finite) are skipped.
  void record(const std::string& camera_id, uint64_t seq, const cv::Mat& depth, const PinholeIntrinsics& intrinsics,
              const Pose& camera_to_world, float min_depth, float max_depth);
  void clear();

  // Up to max_frames frames that saw any of the leaves (origins, sorted or not), most leaves
  // first then newest first; `total` gets how many distinct frames did, of those the leaves
  // remember (each its latest kFramesPerLeaf).
  std::vector<FrameRef> framesSeeing(const std::vector<openvdb::Coord>& leaves, std::size_t max_frames,
                                     uint32_t& total) const;
  std::size_t frameCount() const;
  // Changes with every record() and clear(): answers of framesSeeing() taken at another version
  // may be out of date.
  uint64_t version() const;

 private:
  struct LeafFrames {
    uint32_t frames[kFramesPerLeaf];  // frame numbers, a ring
    uint32_t count = 0;               // ever recorded
  };
  struct CoordHash {
    std::size_t operator()(const openvdb::Coord& c) const {
      return (static_cast<std::size_t>(c.x()) * 73856093u) ^ (static_cast<std::size_t>(c.y()) * 19349663u) ^
             (static_cast<std::size_t>(c.z()) * 83492791u);
    }
  };

  double voxel_size_;
  mutable std::mutex mutex_;
  std::vector<std::string> cameras_;  // interned camera ids
  struct FrameRecord {
    uint32_t camera;
    uint64_t seq;
  };
  std::deque<FrameRecord> frames_;  // frame number first_frame_ + i
  uint32_t first_frame_ = 0;
  uint64_t version_ = 0;
  std::unordered_map<openvdb::Coord, LeafFrames, CoordHash> leaves_;
};

}  // namespace semfuse::objects
