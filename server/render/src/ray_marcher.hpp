#pragma once
// One ray through the TSDF: the march and zero-crossing search behind raycast(). Internal.
//
// Everything happens in index space (voxel (i,j,k) centred at (i,j,k)): the ray is transformed
// once, samples read the packed voxels straight from leaf buffers through one cached accessor,
// and the tree's sparsity is used at every level a ray can skip:
//   - no leaf at the sample: jump to the exit of the missing leaf / internal node (its tile);
//   - a leaf, but the 8^3, 4^3, 2^3 or 1 voxel block around the sample was never observed
//     (inactive in the leaf's value mask): jump to that block's exit;
//   - observed and in front of the surface: sphere-trace by the TSDF value.
#include <limits>

#include <Eigen/Core>

#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

// A ray p(t) = origin + t * direction in world metres; with direction = R * (x, y, 1), t is the
// camera depth.
struct MarchRay {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
  double t_min = 0.0;
  double t_max = 0.0;
};

// Marches rays. Owns a tree accessor, so one per thread; cheap to construct.
class RayMarcher {
 public:
  // skip_empty_space false: no tree-based skipping at all, half-voxel steps wherever the TSDF is
  // unknown (the reference the skipping is checked and benchmarked against).
  RayMarcher(const volume::LabeledVolume& volume, bool skip_empty_space);

  // Depth t of the first positive-to-negative crossing of the trilinear TSDF in [t_min, t_max);
  // false when none.
  bool findSurface(const MarchRay& ray, double& t_surface);

  // Trilinear TSDF in voxel units at a continuous index-space point; false where any of the 8
  // corners is unobserved.
  bool sample(const Eigen::Vector3d& index, float& tsdf_voxels);

 private:
  using Accessor = volume::GeometryGrid::ConstAccessor;
  using Leaf = volume::GeometryGrid::TreeType::LeafNodeType;

  // The leaf a ray is in, with its value buffer: consecutive samples mostly stay in one leaf, so
  // the tree lookup and the buffer's load check run once per leaf, not once per sample.
  struct LeafView {
    const Leaf* leaf = nullptr;  // null where no leaf is allocated
    const volume::PackedVoxel* values = nullptr;
    openvdb::Coord origin{std::numeric_limits<openvdb::Int32>::max()};  // matches no real leaf
  };
  // Points `view` at the leaf (or missing leaf) that holds voxel `ijk`.
  void enterLeaf(const openvdb::Coord& ijk, LeafView& view) {
    const openvdb::Coord origin = ijk & ~(Leaf::DIM - 1);
    if (origin == view.origin) return;
    view.origin = origin;
    view.leaf = accessor_.probeConstLeaf(ijk);
    view.values = view.leaf ? view.leaf->buffer().data() : nullptr;
  }

  // Reads the 8 packed corners of the cell at `base` (corner = dx + 2 dy + 4 dz), `view` being
  // the leaf that holds `base`; false as soon as one is unobserved.
  bool gatherCorners(const LeafView& view, const openvdb::Coord& base, volume::PackedVoxel corners[8]);
  bool sampleAt(const LeafView& view, const openvdb::Coord& base, const Eigen::Vector3d& index, float& tsdf_voxels);

  Accessor accessor_;
  double inv_voxel_size_;
  bool skip_empty_space_;
};

}  // namespace semfuse::render::detail
