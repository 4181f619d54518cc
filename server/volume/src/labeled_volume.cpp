#include "semfuse/volume/labeled_volume.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <iterator>
#include <utility>

namespace semfuse::volume {
namespace {
openvdb::math::Transform::Ptr voxelTransform(double voxel_size) {
  return openvdb::math::Transform::createLinearTransform(voxel_size);
}
}  // namespace

Result<LabeledVolume> LabeledVolume::create(const VolumeParams& params) {
  if (Status status = params.validate(); !status) return makeError("invalid volume parameters: " + status.error());
  return LabeledVolume(params);
}

LabeledVolume::LabeledVolume(const VolumeParams& params)
    : params_(params), leaf_revisions_(std::make_shared<RevisionTree>(0)) {
  assert(params_.validate().ok());
  openvdb::initialize();  // idempotent; registers grid types for I/O
  geometry_ = GeometryGrid::create(kUnobservedVoxel);
  geometry_->setTransform(voxelTransform(params_.voxel_size));
  geometry_->setName("semfuse_geometry");
  if (params_.integrate_color) {
    color_ = ColorGrid::create(0);
    color_->setTransform(voxelTransform(params_.voxel_size));
    color_->setName("color");
  }
  if (usesLabelSidecar(params_.label_rule)) {
    label_sidecar_ = LabelSidecarGrid::create(0);
    label_sidecar_->setTransform(voxelTransform(params_.voxel_size));
    label_sidecar_->setName("label_candidates");
  }
}

bool LabeledVolume::instancesSeenApart(uint32_t a, uint32_t b) const { return hasInstancePair(instances_apart_, a, b); }

void LabeledVolume::markInstancesSeenApart(std::vector<uint64_t> pair_keys) {
  std::sort(pair_keys.begin(), pair_keys.end());
  pair_keys.erase(std::unique(pair_keys.begin(), pair_keys.end()), pair_keys.end());
  // Most frames see pairs the map knows: merge only when one is new.
  const bool any_new = std::any_of(pair_keys.begin(), pair_keys.end(), [&](uint64_t key) {
    return !std::binary_search(instances_apart_.begin(), instances_apart_.end(), key);
  });
  if (!any_new) return;
  std::vector<uint64_t> merged;
  merged.reserve(instances_apart_.size() + pair_keys.size());
  std::set_union(instances_apart_.begin(), instances_apart_.end(), pair_keys.begin(), pair_keys.end(),
                 std::back_inserter(merged));
  instances_apart_ = std::move(merged);
}

LabeledVolume LabeledVolume::deepCopy() const {
  LabeledVolume copy(params_);
  copy.geometry_ = geometry_->deepCopy();
  if (color_) copy.color_ = color_->deepCopy();
  if (label_sidecar_) copy.label_sidecar_ = label_sidecar_->deepCopy();
  if (instances_) copy.instances_ = instances_->deepCopy();
  copy.next_instance_id_ = next_instance_id_;
  copy.instances_apart_ = instances_apart_;
  if (free_space_) copy.free_space_ = free_space_->deepCopy();
  copy.frames_integrated_ = frames_integrated_;
  copy.leaf_revisions_ = std::make_shared<RevisionTree>(*leaf_revisions_);
  copy.revision_ = revision_;
  copy.replaced_at_ = replaced_at_;
  return copy;
}

openvdb::Coord LabeledVolume::worldToIndex(const Eigen::Vector3d& world) const {
  const Eigen::Vector3d index = world / voxelSize();
  // A point beyond OpenVDB's int coordinates (a query 1e12 m away) clamps to their edge, where
  // nothing is ever stored, instead of overflowing the conversion (undefined behaviour; found by
  // fuzz/targets/service_requests.cpp). NaN, which has no voxel, goes to the same edge.
  const auto nearest = [](double v) {
    constexpr double kEdge = 2147483520.0;  // just inside INT_MAX, exact as a double
    const double rounded = std::floor(v + 0.5);
    return static_cast<int>(rounded >= -kEdge && rounded <= kEdge ? rounded : (rounded < 0.0 ? -kEdge : kEdge));
  };
  return {nearest(index.x()), nearest(index.y()), nearest(index.z())};
}

Eigen::Vector3d LabeledVolume::indexToWorld(const openvdb::Coord& ijk) const {
  return Eigen::Vector3d(ijk.x(), ijk.y(), ijk.z()) * voxelSize();
}

Rgb8 LabeledVolume::color(const openvdb::Coord& ijk) const {
  if (!color_) return {};
  return unpackColor(color_->tree().getValue(ijk));
}

void LabeledVolume::clear() {
  geometry_->clear();
  if (color_) color_->clear();
  if (label_sidecar_) label_sidecar_->clear();
  instances_.reset();
  next_instance_id_ = 1;
  instances_apart_.clear();
  if (free_space_) free_space_->clear();
  frames_integrated_ = 0;
  leaf_revisions_->clear();
  replaced_at_ = ++revision_;
}

FreeSpaceGrid& LabeledVolume::mutableFreeSpaceGrid() {
  if (!free_space_) {
    free_space_ = FreeSpaceGrid::create(false);
    free_space_->setTransform(voxelTransform(params_.voxel_size));
    free_space_->setName("free_space");
  }
  return *free_space_;
}

void LabeledVolume::setFreeSpaceGrid(FreeSpaceGrid::Ptr grid) {
  free_space_ = std::move(grid);
  if (!free_space_) return;
  free_space_->setTransform(voxelTransform(params_.voxel_size));
  free_space_->setName("free_space");
}

namespace {
constexpr int kLeafLog2 = 3;
openvdb::Coord leafKey(const openvdb::Coord& origin) {
  return {origin.x() >> kLeafLog2, origin.y() >> kLeafLog2, origin.z() >> kLeafLog2};
}
openvdb::Coord keyOrigin(const openvdb::Coord& key) {
  return {key.x() * (1 << kLeafLog2), key.y() * (1 << kLeafLog2), key.z() * (1 << kLeafLog2)};
}
}  // namespace

void LabeledVolume::markChanged(const std::vector<openvdb::Coord>& leaf_origins) {
  ++revision_;
  openvdb::tree::ValueAccessor<RevisionTree> stamps(*leaf_revisions_);
  for (const openvdb::Coord& origin : leaf_origins) stamps.setValueOn(leafKey(origin), static_cast<int64_t>(revision_));
}

void LabeledVolume::continueRevisionsFrom(uint64_t previous_revision) {
  revision_ = previous_revision + 1;
  replaced_at_ = revision_;
  leaf_revisions_->clear();
}

LabeledVolume::LeafChanges LabeledVolume::changesSince(uint64_t revision) const {
  LeafChanges changes;
  changes.revision = revision_;
  changes.all = revision < replaced_at_;
  if (changes.all) {
    // Every leaf that holds anything: geometry leaves and observed free regions.
    openvdb::MaskTree keys;
    openvdb::tree::ValueAccessor<openvdb::MaskTree> marks(keys);
    for (auto leaf = geometry_->tree().cbeginLeaf(); leaf; ++leaf) marks.setValueOn(leafKey(leaf->origin()));
    if (free_space_) {
      // Observed regions are whole leaves, kept as tiles (or, after a merge, dense leaves).
      for (auto it = free_space_->tree().cbeginValueOn(); it; ++it) {
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        const openvdb::Coord lo = leafKey(box.min()), hi = leafKey(box.max());
        for (int x = lo.x(); x <= hi.x(); ++x)
          for (int y = lo.y(); y <= hi.y(); ++y)
            for (int z = lo.z(); z <= hi.z(); ++z) marks.setValueOn({x, y, z});
      }
    }
    changes.leaves.reserve(keys.activeVoxelCount());
    for (auto it = keys.cbeginValueOn(); it; ++it) changes.leaves.push_back(keyOrigin(it.getCoord()));
    return changes;
  }
  for (auto it = leaf_revisions_->cbeginValueOn(); it; ++it)
    if (static_cast<uint64_t>(*it) > revision) changes.leaves.push_back(keyOrigin(it.getCoord()));
  return changes;
}

InstanceGrid& LabeledVolume::mutableInstanceGrid() {
  if (!instances_) {
    instances_ = InstanceGrid::create(0);
    instances_->setTransform(voxelTransform(params_.voxel_size));
    instances_->setName("instance");
  }
  return *instances_;
}

void LabeledVolume::setInstanceGrid(InstanceGrid::Ptr grid) {
  instances_ = std::move(grid);
  if (instances_) {
    instances_->setTransform(voxelTransform(params_.voxel_size));
    instances_->setName("instance");
  }
}

}  // namespace semfuse::volume
