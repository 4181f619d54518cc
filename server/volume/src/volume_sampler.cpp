#include "semfuse/volume/volume_sampler.hpp"

#include <cmath>

namespace semfuse::volume {
namespace {
using GeometryLeaf = GeometryGrid::TreeType::LeafNodeType;
constexpr int kLeafMask = GeometryLeaf::DIM - 1;

// Offsets of the 8 corners inside one leaf buffer, corner index = dx + 2 dy + 4 dz.
// OpenVDB leaves store z fastest: offset = x * 64 + y * 8 + z.
constexpr int kCornerOffsets[8] = {0, 64, 8, 72, 1, 65, 9, 73};

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
      corners[i] = values[kCornerOffsets[i]];
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

bool VolumeSampler::tsdf(const Eigen::Vector3f& world, float& tsdf) {
  const Eigen::Vector3f index = world * inv_voxel_size_;
  const openvdb::Coord base = floorCoord(index);
  PackedVoxel corners[8];
  if (!gatherCorners(base, corners)) return false;
  const float fx = index.x() - base.x(), fy = index.y() - base.y(), fz = index.z() - base.z();
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = unpackTsdf(corners[i]);
  const float a00 = v[0] + (v[1] - v[0]) * fx, a10 = v[2] + (v[3] - v[2]) * fx;
  const float a01 = v[4] + (v[5] - v[4]) * fx, a11 = v[6] + (v[7] - v[6]) * fx;
  const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
  tsdf = b0 + (b1 - b0) * fz;
  return true;
}

bool VolumeSampler::tsdfAndGradient(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& gradient) {
  const Eigen::Vector3f index = world * inv_voxel_size_;
  const openvdb::Coord base = floorCoord(index);
  PackedVoxel corners[8];
  if (!gatherCorners(base, corners)) return false;
  const float fx = index.x() - base.x(), fy = index.y() - base.y(), fz = index.z() - base.z();
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = unpackTsdf(corners[i]);
  // Differences along x for the four (y, z) edges, then the analytic derivative of the trilinear
  // interpolant: exact for the model the value comes from, so tracking's Jacobian matches it.
  const float dx00 = v[1] - v[0], dx10 = v[3] - v[2], dx01 = v[5] - v[4], dx11 = v[7] - v[6];
  const float a00 = v[0] + dx00 * fx, a10 = v[2] + dx10 * fx;
  const float a01 = v[4] + dx01 * fx, a11 = v[6] + dx11 * fx;
  const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
  tsdf = b0 + (b1 - b0) * fz;
  const float gx = (1 - fz) * (dx00 + (dx10 - dx00) * fy) + fz * (dx01 + (dx11 - dx01) * fy);
  const float gy = (1 - fz) * (a10 - a00) + fz * (a11 - a01);
  const float gz = b1 - b0;
  gradient = Eigen::Vector3f(gx, gy, gz) * inv_voxel_size_;
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
