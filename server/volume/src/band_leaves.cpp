#include "band_leaves.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

namespace semfuse::volume::detail {
namespace {
constexpr int kLeafLog2 = 3;  // leaves are 2^3 voxels wide

// Each thread marks leaf keys (leaf origin / 8) in its own OpenVDB mask tree: the accessor caches
// the path to the last mask leaf, and neighbouring rays hit neighbouring leaves, so marking is a
// few nanoseconds and duplicates cost nothing. The trees are merged with a topology union.
using KeyTree = openvdb::MaskTree;

// Marks every unit cell that the segment a -> b passes through (a 3D DDA, Amanatides & Woo 1987):
// from a's cell, step into the neighbour whose face the segment crosses first, until b's cell.
// The band segment of one ray is about one leaf long, so this visits 1-4 cells where sampling
// the segment at every voxel took 2 * truncation / voxel + 1 samples and could still clip a corner.
template <typename Accessor>
void markCellsOnSegment(const Eigen::Vector3f& a, const Eigen::Vector3f& b, Accessor& keys) {
  openvdb::Coord cell(static_cast<int>(std::floor(a.x())), static_cast<int>(std::floor(a.y())),
                      static_cast<int>(std::floor(a.z())));
  const openvdb::Coord last(static_cast<int>(std::floor(b.x())), static_cast<int>(std::floor(b.y())),
                            static_cast<int>(std::floor(b.z())));
  constexpr float kNever = std::numeric_limits<float>::infinity();
  int step[3];
  float t_next[3], t_delta[3];  // segment parameter (0 at a, 1 at b) of the next face crossing
  for (int i = 0; i < 3; ++i) {
    const float delta = b[i] - a[i];
    step[i] = delta > 0.0f ? 1 : (delta < 0.0f ? -1 : 0);
    t_delta[i] = step[i] != 0 ? 1.0f / std::abs(delta) : kNever;
    const float to_face = step[i] > 0 ? static_cast<float>(cell[i] + 1) - a[i] : a[i] - static_cast<float>(cell[i]);
    t_next[i] = step[i] != 0 ? to_face * t_delta[i] : kNever;
  }
  keys.setValueOn(cell);
  // Each step moves one cell closer to `last` along one axis; the bound only guards rounding.
  const int max_steps = std::abs(last.x() - cell.x()) + std::abs(last.y() - cell.y()) + std::abs(last.z() - cell.z());
  for (int n = 0; n < max_steps && cell != last; ++n) {
    const int axis = t_next[0] <= t_next[1] ? (t_next[0] <= t_next[2] ? 0 : 2) : (t_next[1] <= t_next[2] ? 1 : 2);
    cell[axis] += step[axis];
    t_next[axis] += t_delta[axis];
    keys.setValueOn(cell);
  }
  keys.setValueOn(last);  // in case rounding stopped the walk one cell short
}

// Origins of the leaves that the segments [near(d), far(d)] (camera depths) along the rays of the
// sampled valid pixels pass through, in tree order. Parallel over image rows.
template <typename Segment>
std::vector<openvdb::Coord> leavesAlongRays(const FrameView& frame, double voxel_size, int pixel_stride,
                                            Segment segment) {
  // Everything in leaf units, shifted by half a voxel: voxel i's cell is [i - 0.5, i + 0.5), so
  // the leaf holding point p (voxel units) is floor((p + 0.5) / 8), the unit cell of q = (p + 0.5) / 8.
  const float inv_leaf = static_cast<float>(1.0 / (voxel_size * (1 << kLeafLog2)));
  const Eigen::Matrix3f rotation = frame.camera_to_world_rotation * inv_leaf;
  const Eigen::Vector3f origin =
      frame.camera_to_world_translation * inv_leaf + Eigen::Vector3f::Constant(0.5f / (1 << kLeafLog2));

  tbb::enumerable_thread_specific<KeyTree> trees;
  const int rows = (frame.height + pixel_stride - 1) / pixel_stride;
  tbb::parallel_for(tbb::blocked_range<int>(0, rows, 8), [&](const tbb::blocked_range<int>& range) {
    KeyTree& tree = trees.local();
    openvdb::tree::ValueAccessor<KeyTree, /*IsSafe=*/false> keys(tree);
    for (int r = range.begin(); r != range.end(); ++r) {
      const int v = r * pixel_stride;
      const float* depth_row = frame.depth + static_cast<std::size_t>(v) * frame.depth_stride;
      for (int u = 0; u < frame.width; u += pixel_stride) {
        const float d = depth_row[u];
        if (!frame.validDepth(d)) continue;
        const float near = segment.near(d), far = segment.far(d);
        if (!(far > near)) continue;
        const Eigen::Vector3f direction =
            rotation * Eigen::Vector3f((u - frame.cx) / frame.fx, (v - frame.cy) / frame.fy, 1.0f);
        markCellsOnSegment(origin + direction * near, origin + direction * far, keys);
      }
    }
  });

  KeyTree merged;
  for (KeyTree& tree : trees) merged.topologyUnion(tree);
  std::vector<openvdb::Coord> origins;
  origins.reserve(merged.activeVoxelCount());
  for (auto it = merged.cbeginValueOn(); it; ++it) {
    const openvdb::Coord key = it.getCoord();
    origins.emplace_back(key.x() * (1 << kLeafLog2), key.y() * (1 << kLeafLog2), key.z() * (1 << kLeafLog2));
  }
  return origins;
}

}  // namespace

std::vector<openvdb::Coord> bandLeafOrigins(const FrameView& frame, double voxel_size, double truncation,
                                            int pixel_stride) {
  struct Band {
    float trunc;
    float near(float d) const { return std::max(d - trunc, 0.0f); }
    float far(float d) const { return d + trunc; }
  };
  return leavesAlongRays(frame, voxel_size, pixel_stride, Band{static_cast<float>(truncation)});
}

std::vector<openvdb::Coord> freeSpaceLeafOrigins(const FrameView& frame, double voxel_size, double truncation,
                                                 int pixel_stride) {
  struct InFrontOfBand {
    float trunc, min_depth;
    float near(float) const { return min_depth; }
    float far(float d) const { return d - trunc; }
  };
  return leavesAlongRays(frame, voxel_size, pixel_stride,
                         InFrontOfBand{static_cast<float>(truncation), frame.min_depth});
}

}  // namespace semfuse::volume::detail
