#include "map_queries.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>

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

namespace {

// The ids of the objects with a surface voxel within radius of the point.
std::unordered_set<int32_t> idsNear(const openvdb::Int32Tree& ids, const Eigen::Vector3d& point, double radius,
                                    double voxel_size) {
  std::unordered_set<int32_t> near;
  const Eigen::Vector3d lo = (point - Eigen::Vector3d::Constant(radius)) / voxel_size;
  const Eigen::Vector3d hi = (point + Eigen::Vector3d::Constant(radius)) / voxel_size;
  const openvdb::CoordBBox box(
      openvdb::Coord(int(std::floor(lo.x())), int(std::floor(lo.y())), int(std::floor(lo.z()))),
      openvdb::Coord(int(std::ceil(hi.x())), int(std::ceil(hi.y())), int(std::ceil(hi.z()))));
  const double radius2 = radius * radius;
  for (auto leaf = ids.cbeginLeaf(); leaf; ++leaf) {
    if (!box.hasOverlap(leaf->getNodeBoundingBox())) continue;
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      if (*it <= 0 || !box.isInside(it.getCoord())) continue;
      const openvdb::Coord c = it.getCoord();
      if ((Eigen::Vector3d(c.x(), c.y(), c.z()) * voxel_size - point).squaredNorm() <= radius2) near.insert(*it);
    }
  }
  return near;
}

}  // namespace

std::vector<ObjectInstance> selectObjects(const objects::ObjectSet& set, const ObjectsRequest& request,
                                          double voxel_size) {
  std::unordered_set<int32_t> near;
  if (request.near && set.ids) near = idsNear(*set.ids, *request.near, request.radius, voxel_size);
  std::vector<ObjectInstance> out;
  for (const objects::TrackedObject& object : set.objects) {
    if (object.fragment && !request.include_fragments) continue;
    if (request.label != kUnlabeled && object.label != request.label) continue;
    if (object.figures.voxel_count < request.min_voxels) continue;
    if (request.near && !near.count(static_cast<int32_t>(object.id))) continue;
    const objects::ObjectFigures& f = object.figures;
    ObjectInstance instance;
    instance.id = object.id;
    instance.label = object.label;
    instance.bbox_min = f.bbox_min;
    instance.bbox_max = f.bbox_max;
    instance.centroid = f.centroid;
    instance.voxel_count = f.voxel_count;
    instance.mean_confidence = f.mean_confidence;
    instance.area_m2 = f.area_m2;
    instance.box_center = f.box.center;
    instance.box_half_extents = f.box.half_extents;
    instance.box_rotation = Eigen::Quaterniond(f.box.axes);
    instance.fragment = object.fragment;
    instance.frames = object.frames;
    instance.frame_count = object.frame_count;
    out.push_back(std::move(instance));
  }
  return out;
}

}  // namespace semfuse::server
