#include "semfuse/volume/volume_sampler.hpp"

#include <cmath>

#include "semfuse/volume/cell_interpolation.hpp"

namespace semfuse::volume {
namespace {
using GeometryLeaf = GeometryGrid::TreeType::LeafNodeType;
constexpr int kLeafMask = GeometryLeaf::DIM - 1;

openvdb::Coord floorCoord(const Eigen::Vector3f& index) {
  return {static_cast<int>(std::floor(index.x())), static_cast<int>(std::floor(index.y())),
          static_cast<int>(std::floor(index.z()))};
}
}  // namespace

VolumeSampler::VolumeSampler(const LabeledVolume& volume)
    : volume_(&volume),
      inv_voxel_size_(static_cast<float>(1.0 / volume.voxelSize())),
      voxel_size_(static_cast<float>(volume.voxelSize())),
      geometry_(volume.geometryGrid().getConstAccessor()) {
  if (volume.colorGrid()) color_.emplace(volume.colorGrid()->getConstAccessor());
}

bool VolumeSampler::gatherCorners(const openvdb::Coord& base, PackedVoxel corners[8]) {
  // Two thirds of the time all 8 corners share one leaf: one tree lookup, then plain loads.
  if ((base.x() & kLeafMask) != kLeafMask && (base.y() & kLeafMask) != kLeafMask &&
      (base.z() & kLeafMask) != kLeafMask) {
    const GeometryLeaf* leaf = geometry_.probeConstLeaf(base);
    if (!leaf) return false;
    const PackedVoxel* values = leaf->buffer().data() + GeometryLeaf::coordToOffset(base);
    for (int i = 0; i < 8; ++i) {
      corners[i] = values[kCellCornerOffsets[i]];
      if (!isObserved(corners[i])) return false;
    }
    return true;
  }
  for (int i = 0; i < 8; ++i) {
    const openvdb::Coord ijk = base.offsetBy(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    corners[i] = geometry_.getValue(ijk);
    if (!isObserved(corners[i])) return false;
  }
  return true;
}

bool VolumeSampler::cellAt(const Eigen::Vector3f& world, openvdb::Coord& base, Eigen::Vector3f& fraction,
                           float tsdf[8]) {
  const Eigen::Vector3f index = world * inv_voxel_size_;
  base = floorCoord(index);
  PackedVoxel corners[8];
  if (!gatherCorners(base, corners)) return false;
  fraction =
      index - Eigen::Vector3f(static_cast<float>(base.x()), static_cast<float>(base.y()), static_cast<float>(base.z()));
  for (int i = 0; i < 8; ++i) tsdf[i] = unpackTsdf(corners[i]);
  return true;
}

bool VolumeSampler::tsdf(const Eigen::Vector3f& world, float& tsdf) {
  openvdb::Coord base;
  Eigen::Vector3f f;
  float v[8];
  if (!cellAt(world, base, f, v)) return false;
  tsdf = trilinear(v, f.x(), f.y(), f.z());
  return true;
}

bool VolumeSampler::tsdfAndGradient(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& gradient) {
  openvdb::Coord base;
  Eigen::Vector3f f;
  float v[8];
  if (!cellAt(world, base, f, v)) return false;
  tsdf = trilinearWithGradient(v, f.x(), f.y(), f.z(), gradient);
  gradient *= inv_voxel_size_;
  return true;
}

void VolumeSampler::gatherLuma(const openvdb::Coord& base, float luma[8]) {
  using ColorLeaf = ColorGrid::TreeType::LeafNodeType;
  if ((base.x() & kLeafMask) != kLeafMask && (base.y() & kLeafMask) != kLeafMask &&
      (base.z() & kLeafMask) != kLeafMask) {
    if (const ColorLeaf* leaf = color_->probeConstLeaf(base)) {
      const PackedColor* values = leaf->buffer().data() + ColorLeaf::coordToOffset(base);
      for (int i = 0; i < 8; ++i) luma[i] = unpackLuma(values[kCellCornerOffsets[i]]);
      return;
    }
  }
  for (int i = 0; i < 8; ++i) luma[i] = unpackLuma(color_->getValue(base.offsetBy(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
}

bool VolumeSampler::tsdfAndIntensity(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& tsdf_gradient,
                                     float& intensity, Eigen::Vector3f& intensity_gradient, bool& has_intensity) {
  openvdb::Coord base;
  Eigen::Vector3f f;
  float v[8];
  if (!cellAt(world, base, f, v)) return false;
  tsdf = trilinearWithGradient(v, f.x(), f.y(), f.z(), tsdf_gradient);
  tsdf_gradient *= inv_voxel_size_;
  has_intensity = color_.has_value();
  if (has_intensity) {
    float luma[8];
    gatherLuma(base, luma);
    intensity = trilinearWithGradient(luma, f.x(), f.y(), f.z(), intensity_gradient);
    intensity_gradient *= inv_voxel_size_;
  }
  return true;
}

bool VolumeSampler::nearestVoxel(const Eigen::Vector3f& world, VoxelValue& voxel) {
  const Eigen::Vector3f index = world * inv_voxel_size_ + Eigen::Vector3f::Constant(0.5f);
  const PackedVoxel packed = geometry_.getValue(floorCoord(index));
  if (!isObserved(packed)) return false;
  voxel = unpackVoxel(packed);
  return true;
}

bool VolumeSampler::nearestColor(const Eigen::Vector3f& world, Rgb8& color) {
  if (!color_) return false;
  const Eigen::Vector3f index = world * inv_voxel_size_ + Eigen::Vector3f::Constant(0.5f);
  const openvdb::Coord ijk = floorCoord(index);
  if (!isObserved(geometry_.getValue(ijk))) return false;
  color = unpackColor(color_->getValue(ijk));
  return true;
}

}  // namespace semfuse::volume
