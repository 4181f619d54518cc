#include "map_queries.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

#include <openvdb/math/BBox.h>

namespace semfuse::server {
namespace {

bool isSurface(const volume::VoxelValue& v, double voxel_size) {
  return v.weight > 0.0f && std::abs(v.tsdf) < 0.5 * voxel_size;
}

struct CoordHash {
  size_t operator()(const openvdb::Coord& c) const {
    return (static_cast<size_t>(c.x()) * 73856093u) ^ (static_cast<size_t>(c.y()) * 19349663u) ^
           (static_cast<size_t>(c.z()) * 83492791u);
  }
};

}  // namespace

std::vector<VoxelSample> sampleAt(const volume::LabeledVolume& volume, const std::vector<Eigen::Vector3d>& points) {
  std::vector<VoxelSample> samples;
  samples.reserve(points.size());
  auto accessor = volume.geometryGrid().getConstAccessor();
  for (const auto& point : points) {
    VoxelSample sample;
    if (point.allFinite()) {
      const openvdb::Coord ijk = volume.worldToIndex(point);
      const volume::VoxelValue v = volume::unpackVoxel(accessor.getValue(ijk));
      sample.observed = v.weight > 0.0f;
      if (sample.observed) {
        sample.label = v.label;
        sample.confidence = v.score;
        sample.tsdf = v.tsdf;
        sample.weight = v.weight;
      }
    }
    samples.push_back(sample);
  }
  return samples;
}

RegionSummary summarizeRegion(const volume::LabeledVolume& volume, const Eigen::Vector3d& min,
                              const Eigen::Vector3d& max) {
  RegionSummary summary;
  std::map<LabelId, LabelArea> labels;  // in label order
  const double voxel = volume.voxelSize();
  const openvdb::Coord lo = volume.worldToIndex(min);
  const openvdb::Coord hi = volume.worldToIndex(max);
  const openvdb::CoordBBox box(lo, hi);
  for (auto it = volume.geometryGrid().cbeginValueOn(); it; ++it) {
    if (!it.isVoxelValue() || !box.isInside(it.getCoord())) continue;
    const volume::VoxelValue v = volume::unpackVoxel(*it);
    if (v.weight <= 0.0f) continue;
    ++summary.observed_voxels;
    if (v.tsdf < 0.0f) ++summary.occupied_voxels;
    else ++summary.free_voxels;
    if (isSurface(v, voxel)) {
      LabelArea& area = labels[v.label];
      ++area.surface_voxels;
      area.area_m2 += voxel * voxel;
    }
  }
  for (const auto& [label, area] : labels) summary.histogram.push_back({label, area.surface_voxels, area.area_m2});
  if (summary.observed_voxels > 0)
    summary.occupancy = static_cast<double>(summary.occupied_voxels) / static_cast<double>(summary.observed_voxels);
  return summary;
}

std::vector<ObjectInstance> findObjects(const volume::LabeledVolume& volume, const LabelLegend& legend, LabelId label,
                                        uint64_t min_voxels) {
  const double voxel = volume.voxelSize();
  // Surface voxels of the requested label(s), then flood fill over 26-neighbours.
  std::unordered_map<openvdb::Coord, std::pair<LabelId, float>, CoordHash> surface;
  for (auto it = volume.geometryGrid().cbeginValueOn(); it; ++it) {
    if (!it.isVoxelValue()) continue;
    const volume::VoxelValue v = volume::unpackVoxel(*it);
    if (!isSurface(v, voxel) || v.label == kUnlabeled || legend.isBackground(v.label)) continue;
    if (label != kUnlabeled && v.label != label) continue;
    surface.emplace(it.getCoord(), std::make_pair(v.label, v.score));
  }

  std::vector<ObjectInstance> objects;
  std::vector<openvdb::Coord> stack;
  while (!surface.empty()) {
    auto seed = surface.begin();
    ObjectInstance object;
    object.label = seed->second.first;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double score_sum = 0.0;
    openvdb::CoordBBox bounds;
    score_sum += seed->second.second;
    stack.assign(1, seed->first);
    surface.erase(seed);
    while (!stack.empty()) {
      const openvdb::Coord c = stack.back();
      stack.pop_back();
      ++object.voxel_count;
      bounds.expand(c);
      sum += volume.indexToWorld(c);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            auto next = surface.find(c.offsetBy(dx, dy, dz));
            if (next == surface.end() || next->second.first != object.label) continue;
            score_sum += next->second.second;
            stack.push_back(next->first);
            surface.erase(next);
          }
    }
    if (object.voxel_count < std::max<uint64_t>(min_voxels, 1)) continue;
    object.centroid = sum / static_cast<double>(object.voxel_count);
    object.bbox_min = volume.indexToWorld(bounds.min()) - Eigen::Vector3d::Constant(voxel / 2);
    object.bbox_max = volume.indexToWorld(bounds.max()) + Eigen::Vector3d::Constant(voxel / 2);
    object.mean_confidence = static_cast<float>(score_sum / static_cast<double>(object.voxel_count));
    objects.push_back(object);
  }
  std::sort(objects.begin(), objects.end(),
            [](const ObjectInstance& a, const ObjectInstance& b) { return a.voxel_count > b.voxel_count; });
  for (size_t i = 0; i < objects.size(); ++i) objects[i].id = static_cast<uint32_t>(i + 1);
  return objects;
}

}  // namespace semfuse::server
