#pragma once
// LeafCacheSampler: VolumeSampler's trilinear TSDF and intensity, with their gradients, for points
// scattered over the map and read again pass after pass (tracking: a few thousand points a pass,
// most of them a leaf or more apart, so a tree accessor's cached path rarely helps). It keeps the
// leaves it has found, of the geometry and the colour grid together, in a hash table keyed by leaf
// origin: after the first pass over a frame's points a sample costs a probe and plain loads. Same
// values and validity rule as VolumeSampler. One per thread; the volume must not change while a
// sampler exists (the table holds pointers into its leaves).
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {

class LeafCacheSampler {
 public:
  explicit LeafCacheSampler(const LabeledVolume& volume);

  // As VolumeSampler::tsdfAndGradient and VolumeSampler::tsdfAndIntensity.
  bool tsdfAndGradient(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& gradient);
  bool tsdfAndIntensity(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& tsdf_gradient, float& intensity,
                        Eigen::Vector3f& intensity_gradient, bool& has_intensity);

  // Leaf origins looked up in the trees so far (with or without a leaf there).
  std::size_t leavesLookedUp() const { return used_; }

 private:
  // The voxels of one leaf origin in both grids; null where the grid has no leaf there.
  struct LeafPair {
    const PackedVoxel* geometry = nullptr;
    const PackedColor* color = nullptr;
  };
  struct Slot {
    openvdb::Coord origin;  // kEmptyOrigin: free
    LeafPair leaves;
  };

  // The cell holding `world`: its base voxel and the point's fraction within it; false for points
  // that are not finite or lie beyond every voxel coordinate.
  bool cellAt(const Eigen::Vector3f& world, openvdb::Coord& base, Eigen::Vector3f& fraction) const;
  const LeafPair& leavesAt(const openvdb::Coord& origin);
  const LeafPair& lookUpAndInsert(const openvdb::Coord& origin, std::size_t slot);
  void grow();
  // The 8 corners of the cell at `base` (cell_interpolation.hpp's order): TSDF, and luma where
  // `luma` is not null; false if any corner is unobserved.
  bool gatherCell(const openvdb::Coord& base, float tsdf[8], float* luma);

  float inv_voxel_size_;
  GeometryGrid::ConstAccessor geometry_;
  std::optional<ColorGrid::ConstAccessor> color_;  // empty when the volume has no colour
  float background_luma_ = 0.0f;                   // of the colour grid's background value
  std::vector<Slot> slots_;                        // open addressing, linear probing, power-of-two size
  std::size_t used_ = 0;
  // The last leaf origin looked up: neighbouring points of an image row often share a leaf.
  openvdb::Coord last_origin_;
  const LeafPair* last_ = nullptr;
};

}  // namespace semfuse::volume
