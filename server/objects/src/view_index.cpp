#include "semfuse/objects/view_index.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace semfuse::objects {
namespace {
constexpr int kPixelStride = 8;
}  // namespace

void ViewIndex::record(const std::string& camera_id, uint64_t seq, const cv::Mat& depth,
                       const PinholeIntrinsics& intrinsics, const Pose& camera_to_world, float min_depth,
                       float max_depth) {
  if (depth.type() != CV_32FC1 || depth.empty() || intrinsics.fx <= 0 || intrinsics.fy <= 0) return;
  // The leaves this frame saw, found without the lock.
  std::unordered_set<openvdb::Coord, CoordHash> seen;
  const Eigen::Matrix3d rotation = camera_to_world.linear();
  const Eigen::Vector3d translation = camera_to_world.translation();
  for (int v = kPixelStride / 2; v < depth.rows; v += kPixelStride) {
    const float* row = depth.ptr<float>(v);
    for (int u = kPixelStride / 2; u < depth.cols; u += kPixelStride) {
      const float d = row[u];
      if (!(d >= min_depth && d <= max_depth)) continue;
      const Eigen::Vector3d camera((u - intrinsics.cx) / intrinsics.fx * d, (v - intrinsics.cy) / intrinsics.fy * d, d);
      const Eigen::Vector3d index = (rotation * camera + translation) / voxel_size_;
      if (!index.allFinite() || index.cwiseAbs().maxCoeff() > 1e9) continue;
      const openvdb::Coord voxel(static_cast<int>(std::floor(index.x() + 0.5)),
                                 static_cast<int>(std::floor(index.y() + 0.5)),
                                 static_cast<int>(std::floor(index.z() + 0.5)));
      seen.insert(voxel & ~7);
    }
  }
  std::lock_guard lock(mutex_);
  const auto camera = static_cast<uint32_t>(std::find(cameras_.begin(), cameras_.end(), camera_id) - cameras_.begin());
  if (camera == cameras_.size()) cameras_.push_back(camera_id);
  ++version_;
  const uint32_t number = first_frame_ + static_cast<uint32_t>(frames_.size());
  frames_.push_back({camera, seq});
  if (frames_.size() > kMaxFrames) {
    frames_.pop_front();
    ++first_frame_;
  }
  for (const openvdb::Coord& leaf : seen) {
    LeafFrames& frames = leaves_[leaf];
    frames.frames[frames.count % kFramesPerLeaf] = number;
    ++frames.count;
  }
}

void ViewIndex::clear() {
  std::lock_guard lock(mutex_);
  frames_.clear();
  leaves_.clear();
  first_frame_ = 0;
  ++version_;
}

uint64_t ViewIndex::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

std::size_t ViewIndex::frameCount() const {
  std::lock_guard lock(mutex_);
  return frames_.size();
}

std::vector<FrameRef> ViewIndex::framesSeeing(const std::vector<openvdb::Coord>& leaves, std::size_t max_frames,
                                              uint32_t& total) const {
  std::unordered_map<uint32_t, uint32_t> hits;  // frame number -> leaves it saw
  std::lock_guard lock(mutex_);
  for (const openvdb::Coord& leaf : leaves) {
    const auto found = leaves_.find(leaf);
    if (found == leaves_.end()) continue;
    const LeafFrames& frames = found->second;
    const uint32_t kept = std::min<uint32_t>(frames.count, kFramesPerLeaf);
    for (uint32_t i = 0; i < kept; ++i)
      if (frames.frames[i] >= first_frame_) ++hits[frames.frames[i]];
  }
  std::vector<std::pair<uint32_t, uint32_t>> ranked(hits.begin(), hits.end());
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    return a.second > b.second || (a.second == b.second && a.first > b.first);
  });
  total = static_cast<uint32_t>(ranked.size());
  std::vector<FrameRef> out;
  for (std::size_t i = 0; i < ranked.size() && i < max_frames; ++i) {
    const FrameRecord& record = frames_[ranked[i].first - first_frame_];
    out.push_back({cameras_[record.camera], record.seq});
  }
  return out;
}

}  // namespace semfuse::objects
