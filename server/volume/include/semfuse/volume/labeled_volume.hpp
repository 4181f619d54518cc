#pragma once
// LabeledVolume: the sparse labeled TSDF. Owns the packed geometry+label grid, the optional
// colour grid and the optional label sidecar grid of the top-5 label rules (label_rules.hpp; both
// with the geometry's topology), and knows the voxel <-> world mapping. Voxel (i,j,k) has its centre
// at world (i,j,k) * voxel_size, OpenVDB's cell-centred linear transform.
//
// Integration, sampling and files are free functions / small classes over this type
// (integrator.hpp, volume_sampler.hpp, map_file.hpp); this class only holds the state.
// Not thread-safe for writes: one writer at a time, readers under the caller's shared lock.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <openvdb/openvdb.h>
#include <Eigen/Core>

#include "semfuse/core/result.hpp"
#include "semfuse/volume/instance_evidence.hpp"
#include "semfuse/volume/volume_params.hpp"
#include "semfuse/volume/voxel.hpp"

namespace semfuse::volume {

class LabeledVolume {
 public:
  // Leaves are 8^3 voxels: allocation, iteration and memory figures work in these blocks.
  static constexpr int kLeafDim = GeometryGrid::TreeType::LeafNodeType::DIM;
  static constexpr int kLeafVoxels = GeometryGrid::TreeType::LeafNodeType::SIZE;

  // Checks params; the only way to get a volume from untrusted parameters.
  static Result<LabeledVolume> create(const VolumeParams& params);
  // For parameters known to be valid (defaults, tests): asserts validity in debug builds and
  // sanitises nothing. Prefer create() for anything read from a file or the wire.
  explicit LabeledVolume(const VolumeParams& params = {});

  LabeledVolume(LabeledVolume&&) noexcept = default;
  LabeledVolume& operator=(LabeledVolume&&) noexcept = default;
  LabeledVolume(const LabeledVolume&) = delete;  // grids are large: copy explicitly with deepCopy()
  LabeledVolume& operator=(const LabeledVolume&) = delete;
  LabeledVolume deepCopy() const;
  // Makes this volume, an earlier copy of `source` (deepCopy), equal to `source` again by copying
  // only the leaves `source` changed since this copy's revision; a clear or a replacement since
  // means a whole copy. Cost in proportion to the change, not to the map (volume_catch_up.cpp).
  void catchUpWith(const LabeledVolume& source);

  const VolumeParams& params() const { return params_; }
  double voxelSize() const { return params_.voxel_size; }
  bool hasColor() const { return params_.integrate_color; }

  // Voxel <-> world. worldToIndex rounds to the nearest voxel centre.
  openvdb::Coord worldToIndex(const Eigen::Vector3d& world) const;
  Eigen::Vector3d indexToWorld(const openvdb::Coord& ijk) const;

  // Single-voxel lookups (convenience; use VolumeSampler in loops, it caches tree paths).
  VoxelValue voxel(const openvdb::Coord& ijk) const { return unpackVoxel(packedVoxel(ijk)); }
  VoxelValue voxelAt(const Eigen::Vector3d& world) const { return voxel(worldToIndex(world)); }
  PackedVoxel packedVoxel(const openvdb::Coord& ijk) const { return geometry_->tree().getValue(ijk); }
  // Colour of a voxel; black where there is no colour grid or the voxel was never coloured.
  Rgb8 color(const openvdb::Coord& ijk) const;

  // Size figures. Allocated voxels are all voxels of allocated leaves (what memory is spent on);
  // observed voxels are those with weight > 0 (the grid's active voxels).
  std::size_t allocatedLeaves() const { return geometry_->tree().leafCount(); }
  std::size_t allocatedVoxels() const { return allocatedLeaves() * kLeafVoxels; }
  std::size_t observedVoxels() const { return geometry_->tree().activeVoxelCount(); }
  std::size_t geometryMemoryBytes() const { return geometry_->memUsage(); }
  std::size_t colorMemoryBytes() const { return color_ ? color_->memUsage() : 0; }
  std::size_t labelSidecarMemoryBytes() const { return label_sidecar_ ? label_sidecar_->memUsage() : 0; }
  std::size_t instanceMemoryBytes() const { return instances_ ? instances_->memUsage() : 0; }
  std::size_t memoryBytes() const {
    return geometryMemoryBytes() + colorMemoryBytes() + labelSidecarMemoryBytes() + instanceMemoryBytes();
  }

  // Clears the map: every leaf counts as changed from here on (changesSince says `all`).
  void clear();
  uint64_t framesIntegrated() const { return frames_integrated_; }
  void setFramesIntegrated(uint64_t frames) { frames_integrated_ = frames; }

  // The grids, for render/tracking/mesh code that iterates leaves or builds its own accessors.
  // colorGrid() is null when the volume has no colour.
  const GeometryGrid& geometryGrid() const { return *geometry_; }
  const ColorGrid* colorGrid() const { return color_.get(); }
  ColorGrid::ConstPtr colorGridPtr() const { return color_; }
  // The label rule's runners-up; null when the rule keeps none (evidence).
  const LabelSidecarGrid* labelSidecarGrid() const { return label_sidecar_.get(); }
  LabelSidecarGrid::ConstPtr labelSidecarGridPtr() const { return label_sidecar_; }
  // Mutable access for the integrator and the map loader; keep the topologies identical.
  GeometryGrid& mutableGeometryGrid() { return *geometry_; }
  ColorGrid* mutableColorGrid() { return color_.get(); }
  LabelSidecarGrid* mutableLabelSidecarGrid() { return label_sidecar_.get(); }

  // Panoptic instance evidence (instance_evidence.hpp): null until the first instance map is
  // fused, so a map fused from class-only segmenters carries none. Its leaves are a subset of the
  // geometry's. The next instance id is the one integrateInstances() gives a segment it cannot
  // match to one the map knows.
  const InstanceGrid* instanceGrid() const { return instances_.get(); }
  InstanceGrid::ConstPtr instanceGridPtr() const { return instances_; }
  InstanceGrid& mutableInstanceGrid();  // creates it when missing
  void setInstanceGrid(InstanceGrid::Ptr grid);
  uint32_t nextInstanceId() const { return next_instance_id_; }
  void setNextInstanceId(uint32_t id) { next_instance_id_ = id; }
  // Pairs of map instances one segmentation named as two of its segments: two objects, whatever
  // the geometry says. Instances never seen apart (a box's face first seen alone, the rest of the
  // box later) are one object where the geometry joins them. Keys instancePairKey(low, high).
  bool instancesSeenApart(uint32_t a, uint32_t b) const;
  void markInstancesSeenApart(std::vector<uint64_t> pair_keys);  // instancePairKey()s, any order
  const std::vector<uint64_t>& instancePairsSeenApart() const { return instances_apart_; }  // sorted
  void setInstancePairsSeenApart(std::vector<uint64_t> sorted_keys) { instances_apart_ = std::move(sorted_keys); }

  // Observed free space (free_space.hpp): the voxels a camera saw through, in front of its
  // depth's truncation band (wholly free leaves as level-1 tiles). A voxel is observed when the
  // geometry grid has it active or when it is free here; everything else is unknown. Null until
  // the first frame's free space is observed; kept in map files as the mask grid "free_space".
  const FreeSpaceGrid* freeSpaceGrid() const { return free_space_.get(); }
  FreeSpaceGrid::ConstPtr freeSpaceGridPtr() const { return free_space_; }
  FreeSpaceGrid& mutableFreeSpaceGrid();  // creates it when absent
  void setFreeSpaceGrid(FreeSpaceGrid::Ptr grid);
  bool observedFree(const openvdb::Coord& ijk) const { return free_space_ && free_space_->tree().isValueOn(ijk); }

  // Changed-block tracking. Every write (integrate, integrateLabels, observeFreeSpace) bumps the
  // volume's revision and stamps the leaves it changed with it; clear() and a map replacing
  // another (continueRevisionsFrom) change everything. A consumer that derives something from
  // the map per leaf (the distance field, a live mesh) remembers the revision it is up to date
  // with and asks for what changed since: changesSince(R).leaves are the origins of the leaves
  // written after R; when `all` is set the map was cleared or replaced after R and the consumer
  // rebuilds from every leaf (then listed in `leaves`). Cost: one 64-bit stamp per leaf in a
  // sparse tree (about 0.2 % of the map), and a walk over the stamps per call.
  uint64_t revision() const { return revision_; }
  struct LeafChanges {
    uint64_t revision = 0;  // the volume's revision these changes bring the consumer up to
    bool all = false;
    std::vector<openvdb::Coord> leaves;  // leaf origins (voxel coordinates), in tree order
  };
  LeafChanges changesSince(uint64_t revision) const;
  // Called by the writers: a new revision, stamped on the leaves with these origins.
  void markChanged(const std::vector<openvdb::Coord>& leaf_origins);
  // For a volume that replaces `previous` (a loaded map): its revision continues after previous's
  // and every one of its leaves counts as changed.
  void continueRevisionsFrom(uint64_t previous_revision);

 private:
  VolumeParams params_;
  GeometryGrid::Ptr geometry_;
  ColorGrid::Ptr color_;
  LabelSidecarGrid::Ptr label_sidecar_;
  InstanceGrid::Ptr instances_;
  uint32_t next_instance_id_ = 1;
  std::vector<uint64_t> instances_apart_;  // sorted instancePairKey()s
  FreeSpaceGrid::Ptr free_space_;
  uint64_t frames_integrated_ = 0;
  // Leaf key (origin / 8) -> revision of the leaf's last change. A pointer: OpenVDB trees are not
  // movable, the volume is.
  using RevisionTree = openvdb::Int64Tree;
  std::shared_ptr<RevisionTree> leaf_revisions_;
  uint64_t revision_ = 0;
  uint64_t replaced_at_ = 0;  // revision of the last clear / replacement
};

}  // namespace semfuse::volume
