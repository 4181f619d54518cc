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
}  // namespace

std::vector<openvdb::Coord> bandLeafOrigins(const FrameView& frame, double voxel_size, double truncation,
                                            int pixel_stride) {
  const float inv_voxel = static_cast<float>(1.0 / voxel_size);
  const float trunc = static_cast<float>(truncation);
  // Step along each ray's band at one voxel so that no leaf on the segment is skipped.
  const float step = static_cast<float>(voxel_size);
  const int samples = static_cast<int>(std::ceil(2.0f * trunc / step)) + 1;
  // Everything in voxel index units: index(z) = origin + z * direction(pixel).
  const Eigen::Matrix3f rotation = frame.camera_to_world_rotation * inv_voxel;
  const Eigen::Vector3f origin = frame.camera_to_world_translation * inv_voxel;

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
        const Eigen::Vector3f ray((u - frame.cx) / frame.fx, (v - frame.cy) / frame.fy, 1.0f);
        const Eigen::Vector3f direction = rotation * ray;
        const float z0 = std::max(d - trunc, 0.0f);
        openvdb::Coord last(std::numeric_limits<int>::min());
        for (int i = 0; i < samples; ++i) {
          const float z = std::min(z0 + i * step, d + trunc);
          const Eigen::Vector3f p = origin + direction * z;
          // Voxel i's cell is [i - 0.5, i + 0.5): round to the nearest voxel, then to its leaf.
          const openvdb::Coord key(static_cast<int>(std::floor(p.x() + 0.5f)) >> kLeafLog2,
                                   static_cast<int>(std::floor(p.y() + 0.5f)) >> kLeafLog2,
                                   static_cast<int>(std::floor(p.z() + 0.5f)) >> kLeafLog2);
          if (key != last) keys.setValueOn(key);
          last = key;
        }
      }
    }
  });

  KeyTree merged;
  for (KeyTree& tree : trees) merged.topologyUnion(tree);
  std::vector<openvdb::Coord> origins;
  origins.reserve(merged.activeVoxelCount());
  for (auto it = merged.cbeginValueOn(); it; ++it) {
    const openvdb::Coord key = it.getCoord();
    origins.emplace_back(key.x() * 8, key.y() * 8, key.z() * 8);
  }
  return origins;
}

}  // namespace semfuse::volume::detail
