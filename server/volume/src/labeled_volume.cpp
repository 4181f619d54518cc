#include "semfuse/volume/labeled_volume.hpp"

#include <cassert>
#include <cmath>
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

LabeledVolume::LabeledVolume(const VolumeParams& params) : params_(params) {
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

LabeledVolume LabeledVolume::deepCopy() const {
  LabeledVolume copy(params_);
  copy.geometry_ = geometry_->deepCopy();
  if (color_) copy.color_ = color_->deepCopy();
  if (label_sidecar_) copy.label_sidecar_ = label_sidecar_->deepCopy();
  if (instances_) copy.instances_ = instances_->deepCopy();
  copy.next_instance_id_ = next_instance_id_;
  copy.frames_integrated_ = frames_integrated_;
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
  frames_integrated_ = 0;
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
