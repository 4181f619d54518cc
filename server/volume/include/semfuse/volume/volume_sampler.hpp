#pragma once
// VolumeSampler: fast point queries on a LabeledVolume for raycasting and tracking, which ask
// millions of times per frame. Owns read accessors (they cache the tree path to the last leaf),
// so make one per thread (e.g. tbb::enumerable_thread_specific) and keep it for the whole pass;
// construction is cheap. Never allocates. The volume must outlive the sampler and must not be
// modified while it is in use.
#include <optional>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

class VolumeSampler {
 public:
  explicit VolumeSampler(const LabeledVolume& volume);

  // Trilinearly interpolated TSDF in metres at a world point. False (tsdf untouched) where any of
  // the 8 surrounding voxels is unobserved: interpolating against "unknown" would invent surfaces.
  bool tsdf(const Eigen::Vector3f& world, float& tsdf);
  bool tsdf(const Eigen::Vector3d& world, float& tsdf) {
    return this->tsdf(Eigen::Vector3f(world.cast<float>()), tsdf);
  }

  // Same, plus the gradient of the trilinear interpolant (metres per metre; points away from the
  // surface, towards free space; not normalised). Same validity rule.
  bool tsdfAndGradient(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& gradient);
  bool tsdfAndGradient(const Eigen::Vector3d& world, float& tsdf, Eigen::Vector3f& gradient) {
    return tsdfAndGradient(Eigen::Vector3f(world.cast<float>()), tsdf, gradient);
  }

  // The TSDF and its gradient as above, plus the trilinearly interpolated intensity of the fused
  // colour (luma of the voxels' RGB, 0..1) and its gradient (per metre). has_intensity is false
  // when the volume keeps no colour; the return value is the TSDF's validity.
  bool tsdfAndIntensity(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& tsdf_gradient, float& intensity,
                        Eigen::Vector3f& intensity_gradient, bool& has_intensity);

  // The voxel whose centre is nearest to the point (label, score, tsdf, weight). False where it
  // is unobserved.
  bool nearestVoxel(const Eigen::Vector3f& world, VoxelValue& voxel);
  bool nearestVoxel(const Eigen::Vector3d& world, VoxelValue& voxel) {
    return nearestVoxel(Eigen::Vector3f(world.cast<float>()), voxel);
  }
  // Colour of the nearest voxel; false where unobserved or the volume has no colour.
  bool nearestColor(const Eigen::Vector3f& world, Rgb8& color);

  const LabeledVolume& volume() const { return *volume_; }

 private:
  // Packed values of the 8 voxels around `base` (x fastest, then y, then z); false if any is
  // unobserved.
  bool gatherCorners(const openvdb::Coord& base, PackedVoxel corners[8]);
  // The cell holding `world`: its base voxel, the point's fraction within it and the TSDF at its
  // 8 corners (gatherCorners' order); false if any corner is unobserved.
  bool cellAt(const Eigen::Vector3f& world, openvdb::Coord& base, Eigen::Vector3f& fraction, float tsdf[8]);
  // Luma (0..1) of the 8 colour voxels around `base`, same order; needs a colour grid.
  void gatherLuma(const openvdb::Coord& base, float luma[8]);

  const LabeledVolume* volume_;
  float inv_voxel_size_;
  float voxel_size_;
  GeometryGrid::ConstAccessor geometry_;
  std::optional<ColorGrid::ConstAccessor> color_;  // empty when the volume has no colour
};

}  // namespace semfuse::volume
