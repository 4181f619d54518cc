#include "semfuse/volume/free_space.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "band_leaves.hpp"
#include "frame_view.hpp"

namespace semfuse::volume {
namespace {

using detail::FrameView;

// Every 8th pixel of every 8th row: a leaf is 8 voxels wide, so at indoor distances several
// sampled rays cross each leaf in front of the surface.
constexpr int kFreeSpacePixelStride = 8;

// Min-depth pyramid: level 0 is the depth with invalid pixels as 0, each next level the minimum of
// 2x2 cells. A rectangle's minimum is read from the coarsest level where it spans at most 2x2
// cells, which cover it: a lower bound of the true minimum, never above it.
class MinDepthPyramid {
 public:
  explicit MinDepthPyramid(const FrameView& frame) {
    Level base{frame.width, frame.height, std::vector<float>(static_cast<std::size_t>(frame.width) * frame.height)};
    for (int v = 0; v < frame.height; ++v) {
      const float* row = frame.depth + static_cast<std::size_t>(v) * frame.depth_stride;
      for (int u = 0; u < frame.width; ++u) base.at(u, v) = frame.validDepth(row[u]) ? row[u] : 0.0f;
    }
    levels_.push_back(std::move(base));
    while (levels_.back().width > 1 || levels_.back().height > 1) {
      const Level& fine = levels_.back();
      Level coarse{(fine.width + 1) / 2, (fine.height + 1) / 2, {}};
      coarse.depth.resize(static_cast<std::size_t>(coarse.width) * coarse.height);
      for (int v = 0; v < coarse.height; ++v)
        for (int u = 0; u < coarse.width; ++u) {
          const int u1 = std::min(2 * u + 1, fine.width - 1), v1 = std::min(2 * v + 1, fine.height - 1);
          coarse.at(u, v) = std::min(std::min(fine.at(2 * u, 2 * v), fine.at(u1, 2 * v)),
                                     std::min(fine.at(2 * u, v1), fine.at(u1, v1)));
        }
      levels_.push_back(std::move(coarse));
    }
  }

  // Lower bound of the depths in pixels [u0, u1] x [v0, v1] (inside the image); 0 when any is invalid.
  float minimum(int u0, int v0, int u1, int v1) const {
    std::size_t level = 0;
    while (level + 1 < levels_.size() && ((u1 >> level) - (u0 >> level) > 1 || (v1 >> level) - (v0 >> level) > 1))
      ++level;
    const Level& l = levels_[level];
    float m = std::numeric_limits<float>::infinity();
    for (int v = v0 >> level; v <= (v1 >> level); ++v)
      for (int u = u0 >> level; u <= (u1 >> level); ++u) m = std::min(m, l.at(u, v));
    return m;
  }

 private:
  struct Level {
    int width, height;
    std::vector<float> depth;
    float& at(int u, int v) { return depth[static_cast<std::size_t>(v) * width + u]; }
    float at(int u, int v) const { return depth[static_cast<std::size_t>(v) * width + u]; }
  };
  std::vector<Level> levels_;
};

// Whether the leaf at `origin` lies wholly in the observed empty space of the frame.
bool leafObservedFree(const openvdb::Coord& origin, const FrameView& frame, const MinDepthPyramid& depths, float voxel,
                      float truncation) {
  const float lo[3] = {(origin.x() - 0.5f) * voxel, (origin.y() - 0.5f) * voxel, (origin.z() - 0.5f) * voxel};
  const float size = static_cast<float>(LabeledVolume::kLeafDim) * voxel;
  float u_min = std::numeric_limits<float>::infinity(), v_min = u_min, z_max = 0.0f;
  float u_max = -u_min, v_max = -u_min;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3f world(lo[0] + ((corner & 1) ? size : 0.0f), lo[1] + ((corner & 2) ? size : 0.0f),
                                lo[2] + ((corner & 4) ? size : 0.0f));
    const Eigen::Vector3f c = frame.world_to_camera_rotation * world + frame.world_to_camera_translation;
    if (!(c.z() > frame.min_depth)) return false;
    const float u = frame.fx * c.x() / c.z() + frame.cx, v = frame.fy * c.y() / c.z() + frame.cy;
    u_min = std::min(u_min, u), u_max = std::max(u_max, u);
    v_min = std::min(v_min, v), v_max = std::max(v_max, v);
    z_max = std::max(z_max, c.z());
  }
  // Pixels the voxels of the box round to (the integrator's u + 0.5 truncation).
  const float u0 = std::floor(u_min + 0.5f), u1 = std::floor(u_max + 0.5f);
  const float v0 = std::floor(v_min + 0.5f), v1 = std::floor(v_max + 0.5f);
  if (u0 < 0.0f || v0 < 0.0f || u1 > frame.width - 1.0f || v1 > frame.height - 1.0f) return false;
  const float nearest =
      depths.minimum(static_cast<int>(u0), static_cast<int>(v0), static_cast<int>(u1), static_cast<int>(v1));
  return nearest > 0.0f && z_max < nearest - truncation;
}

// The first local coordinate in [0, 8) whose global coordinate origin + local is a multiple of
// `stride` (stride 1: 0).
int firstSample(int origin, int stride) {
  const int remainder = ((origin % stride) + stride) % stride;
  return remainder == 0 ? 0 : stride - remainder;
}

// The voxels of a leaf that the frame sees as empty, one by one: each voxel centre projects to a
// pixel with valid depth d and lies nearer than d - truncation (as the integrator projects). Only
// voxels whose coordinates are multiples of `stride` are tested. Bit n is the voxel at leaf
// offset n.
using LeafBits = std::array<uint64_t, LabeledVolume::kLeafVoxels / 64>;
bool voxelsObservedFree(const openvdb::Coord& origin, const FrameView& frame, float voxel, float truncation, int stride,
                        LeafBits& bits) {
  bool any = false;
  bits.fill(0);
  constexpr int kDim = LabeledVolume::kLeafDim;
  for (int x = firstSample(origin.x(), stride); x < kDim; x += stride)
    for (int y = firstSample(origin.y(), stride); y < kDim; y += stride)
      for (int z = firstSample(origin.z(), stride); z < kDim; z += stride) {
        const Eigen::Vector3f world((origin.x() + x) * voxel, (origin.y() + y) * voxel, (origin.z() + z) * voxel);
        const Eigen::Vector3f c = frame.world_to_camera_rotation * world + frame.world_to_camera_translation;
        if (!(c.z() > frame.min_depth)) continue;
        const float u = frame.fx * c.x() / c.z() + frame.cx, v = frame.fy * c.y() / c.z() + frame.cy;
        if (!(u >= -0.5f && v >= -0.5f && u < frame.width - 0.5f && v < frame.height - 0.5f)) continue;
        const int ui = static_cast<int>(u + 0.5f), vi = static_cast<int>(v + 0.5f);
        const float d = frame.depth[static_cast<std::size_t>(vi) * frame.depth_stride + ui];
        if (!frame.validDepth(d) || !(c.z() < d - truncation)) continue;
        const int n = (x << 6) | (y << 3) | z;  // OpenVDB's leaf offset
        bits[n >> 6] |= uint64_t{1} << (n & 63);
        any = true;
      }
  return any;
}

enum class LeafVerdict : uint8_t { kNone, kWhole, kSome };

}  // namespace

Result<FreeSpaceStats> observeFreeSpace(LabeledVolume& volume, const cv::Mat& depth,
                                        const PinholeIntrinsics& intrinsics, const Pose& camera_to_world,
                                        int sample_stride) {
  if (sample_stride < 1) return makeError("free space sample stride must be at least 1");
  const VolumeParams& params = volume.params();
  auto view = detail::makeFrameView(params, depth, cv::Mat(), cv::Mat(), cv::Mat(), intrinsics, camera_to_world);
  if (!view) return makeError(view.error());
  const FrameView& frame = view.value();

  FreeSpaceStats stats;
  std::vector<openvdb::Coord> candidates =
      detail::freeSpaceLeafOrigins(frame, params.voxel_size, params.truncation, kFreeSpacePixelStride);
  FreeSpaceGrid& free_space = volume.mutableFreeSpaceGrid();
  // Leaves already wholly free are done; partly free ones are tested again (more may be seen).
  const auto& tree = free_space.tree();
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const openvdb::Coord& origin) {
                                    return tree.isValueOn(origin) && tree.probeConstLeaf(origin) == nullptr;
                                  }),
                   candidates.end());
  stats.candidate_leaves = candidates.size();
  if (candidates.empty()) return stats;

  const MinDepthPyramid depths(frame);
  std::vector<LeafVerdict> verdicts(candidates.size(), LeafVerdict::kNone);
  std::vector<LeafBits> bits(candidates.size());
  const auto voxel = static_cast<float>(params.voxel_size), truncation = static_cast<float>(params.truncation);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, candidates.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (leafObservedFree(candidates[i], frame, depths, voxel, truncation))
                          verdicts[i] = LeafVerdict::kWhole;
                        else if (voxelsObservedFree(candidates[i], frame, voxel, truncation, sample_stride, bits[i]))
                          verdicts[i] = LeafVerdict::kSome;
                      }
                    });
  std::vector<openvdb::Coord> changed;
  openvdb::tree::ValueAccessor<FreeSpaceGrid::TreeType> marks(free_space.tree());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (verdicts[i] == LeafVerdict::kNone) continue;
    if (verdicts[i] == LeafVerdict::kWhole) {
      marks.addTile(/*level=*/1, candidates[i], true, true);  // one 8^3 region, no leaf node
      ++stats.new_free_leaves;
      changed.push_back(candidates[i]);
      continue;
    }
    auto* leaf = marks.touchLeaf(candidates[i]);
    const openvdb::Index before = leaf->onVoxelCount();
    for (int n = 0; n < LabeledVolume::kLeafVoxels; ++n)
      if (bits[i][n >> 6] >> (n & 63) & 1u) leaf->setValueOn(static_cast<openvdb::Index>(n));
    const openvdb::Index after = leaf->onVoxelCount();
    if (after == before) continue;
    stats.new_free_voxels += after - before;
    changed.push_back(candidates[i]);
    if (leaf->isValueMaskOn()) {  // now wholly free: a tile is smaller
      marks.addTile(1, candidates[i], true, true);
      ++stats.new_free_leaves;
    }
  }
  if (!changed.empty()) volume.markChanged(changed);
  return stats;
}

}  // namespace semfuse::volume
