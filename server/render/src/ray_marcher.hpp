#pragma once
// One ray through the TSDF: the march and zero-crossing search behind raycast(). Internal.
#include <Eigen/Core>

#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::render::detail {

// A ray p(t) = origin + t * direction in world metres; with direction = R * (x, y, 1), t is the
// camera depth.
struct MarchRay {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
  double t_min = 0.0;
  double t_max = 0.0;
};

// Marches one ray. Owns accessors, so one per thread, like VolumeSampler.
class RayMarcher {
 public:
  RayMarcher(const volume::LabeledVolume& volume, bool skip_empty_space);

  // Depth t of the first positive-to-negative crossing in [t_min, t_max); false when none.
  bool findSurface(const MarchRay& ray, double& t_surface);

  volume::VolumeSampler& sampler() { return sampler_; }

 private:
  // Where an unallocated region starts at `ijk`, the ray parameter at which the ray leaves that
  // region (a tile or a missing child of the tree, aligned to its node size); t itself when a
  // leaf is there.
  double skipEmpty(const openvdb::Coord& ijk, const Eigen::Vector3d& index_origin,
                   const Eigen::Vector3d& index_direction, double t);
  // Regula falsi on the trilinear interpolant between a positive and a negative sample.
  double refineCrossing(const MarchRay& ray, double t_pos, float f_pos, double t_neg, float f_neg);

  volume::VolumeSampler sampler_;
  volume::GeometryGrid::ConstAccessor accessor_;
  double voxel_size_;
  bool skip_empty_space_;
};

}  // namespace semfuse::render::detail
