#pragma once
// What the distance field's accuracy tests compare against: the room's analytic geometry, the
// surface the field is built from (the TSDF's zero crossings at the map's resolution) and
// percentiles of the errors.
#include <algorithm>
#include <cmath>
#include <vector>

#include "fused_room.hpp"
#include "semfuse/esdf/esdf_map.hpp"
#include "semfuse/esdf/semantic_distance.hpp"

namespace semfuse::esdf::testing {

// Errors in voxels; percentile() sorts them.
struct Errors {
  std::vector<double> values;
  double percentile(double p) {
    if (values.empty()) return 0;
    std::sort(values.begin(), values.end());
    return values[std::min(values.size() - 1, static_cast<std::size_t>(p / 100.0 * values.size()))];
  }
};

inline double analyticDistance(const synthetic::LabeledScene& scene, const Eigen::Vector3d& p) {
  return scene.nearestSurface(p).signed_distance;
}

// The nearest point of the true surface, by the analytic field's gradient.
inline Eigen::Vector3d nearestTruePoint(const synthetic::LabeledScene& scene, const Eigen::Vector3d& p) {
  const double e = 0.25 * kVoxel;
  Eigen::Vector3d g;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    step[a] = e;
    g[a] = (analyticDistance(scene, p + step) - analyticDistance(scene, p - step)) / (2 * e);
  }
  if (g.norm() < 1e-9) return p;
  return p - g.normalized() * analyticDistance(scene, p);
}

// The camera saw the surface there: the TSDF voxel nearest the point is observed near zero.
inline bool surfaceObserved(const volume::LabeledVolume& volume, const Eigen::Vector3d& q) {
  const volume::VoxelValue v = volume.voxelAt(q);
  return v.observed() && std::abs(v.tsdf) < 1.5 * kVoxel;
}

// Every zero crossing of the TSDF (between 6-neighbours observed on both sides), linearly
// interpolated: the surface the field is built from.
inline std::vector<SurfacePoint> tsdfCrossings(const volume::LabeledVolume& volume) {
  std::vector<SurfacePoint> points;
  openvdb::tree::ValueAccessor<const volume::GeometryGrid::TreeType> values(volume.geometryGrid().tree());
  for (auto it = volume.geometryGrid().tree().cbeginValueOn(); it; ++it) {
    const float a = volume::unpackTsdf(*it);
    for (int axis = 0; axis < 3; ++axis) {
      openvdb::Coord next = it.getCoord();
      next[axis] += 1;
      volume::PackedVoxel packed;
      if (!values.probeValue(next, packed)) continue;
      const float b = volume::unpackTsdf(packed);
      if ((a < 0) == (b < 0)) continue;
      Eigen::Vector3f p = centreOf(it.getCoord()).cast<float>();
      p[axis] += static_cast<float>(kVoxel) * std::abs(a) / (std::abs(a) + std::abs(b));
      points.push_back({p, kUnlabeled});
    }
  }
  return points;
}

// How a field differs from another over the same voxels (an incremental field against a
// rebuild), in voxels: every known voxel of `field` looked up in `other`.
struct FieldDifference {
  std::size_t compared = 0;
  std::size_t missing = 0;  // known in `field`, not in `other`
  std::size_t differ = 0;   // by more than half a voxel
  double worst = 0;
};

inline FieldDifference compareFields(const EsdfMap& field, const EsdfMap& other) {
  FieldDifference result;
  openvdb::tree::ValueAccessor<const EsdfGrid::TreeType> values(other.grid().tree());
  const float max_voxels = other.maxDistanceVoxels();
  for (auto it = field.grid().tree().cbeginValueOn(); it; ++it) {
    PackedEsdf packed;
    if (!values.probeValue(it.getCoord(), packed)) {
      ++result.missing;
      continue;
    }
    const double a = unpackEsdf(*it).signedDistance(max_voxels), b = unpackEsdf(packed).signedDistance(max_voxels);
    ++result.compared;
    result.worst = std::max(result.worst, std::abs(a - b));
    result.differ += std::abs(a - b) > 0.5;
  }
  return result;
}

}  // namespace semfuse::esdf::testing
