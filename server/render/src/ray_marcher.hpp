#pragma once
// The plain march behind raycast()'s reference path (RaycastOptions::skip_empty_space = false).
// Internal.
//
// Everything happens in index space (voxel (i,j,k) centred at (i,j,k)): the ray is transformed
// once and samples read the packed voxels straight from leaf buffers through one cached
// accessor. In front of the surface the ray is sphere-traced by the TSDF value, elsewhere it
// steps half a voxel; it skips nothing, which is what makes it the reference that the fast path
// (cell_marcher.hpp) is tested and benchmarked against.
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
  explicit RayMarcher(const volume::LabeledVolume& volume);

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
};

}  // namespace semfuse::render::detail
