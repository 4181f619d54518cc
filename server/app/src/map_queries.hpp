#pragma once
// Read-only questions about the map that the query services answer, as free functions over a
// LabeledVolume (no DDS): what is at these points, what is in this box, which objects exist.
//
// A "surface voxel" is an observed voxel within half a voxel of the zero crossing
// (|tsdf| < voxel_size / 2): a band one voxel thick, so count * voxel_size^2 estimates area.
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/core/legend.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::server {

struct PointSample {
  bool observed = false;
  LabelId label = 0;
  float score = 0.0f;
  float tsdf = 0.0f;
  float weight = 0.0f;
};
std::vector<PointSample> sampleAt(const volume::LabeledVolume& volume, const std::vector<Eigen::Vector3d>& points);

struct RegionSummary {
  struct LabelArea {
    uint64_t surface_voxels = 0;
    double area_m2 = 0.0;
  };
  std::map<LabelId, LabelArea> labels;  // surface voxels per label (0 = unlabeled surface)
  uint64_t observed_voxels = 0;
  uint64_t occupied_voxels = 0;  // observed, behind the surface (tsdf < 0)
  uint64_t free_voxels = 0;      // observed, in front of it (tsdf >= 0)
  double occupancy = 0.0;        // occupied / observed
};
RegionSummary summarizeRegion(const volume::LabeledVolume& volume, const Eigen::Vector3d& min,
                              const Eigen::Vector3d& max);

struct ObjectInstance {
  uint32_t id = 0;
  LabelId label = 0;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  uint64_t voxel_count = 0;
  float mean_score = 0.0f;
};
// Connected (26-neighbourhood) sets of surface voxels sharing one label; label 0 = every label
// (except unlabeled and background). Largest first; those smaller than min_voxels are left out.
std::vector<ObjectInstance> findObjects(const volume::LabeledVolume& volume, const LabelLegend& legend, LabelId label,
                                        uint64_t min_voxels);

}  // namespace semfuse::server
