#include "semfuse/volume/leaf_cache_sampler.hpp"

#include <cmath>
#include <cstdint>

#include "semfuse/volume/cell_interpolation.hpp"

namespace semfuse::volume {
namespace {
using GeometryLeafNode = GeometryGrid::TreeType::LeafNodeType;
using ColorLeafNode = ColorGrid::TreeType::LeafNodeType;
constexpr int kLeafBits = GeometryLeafNode::LOG2DIM;
constexpr int kLeafCoordMask = GeometryLeafNode::DIM - 1;
static_assert(GeometryLeafNode::DIM == ColorLeafNode::DIM, "both grids share one topology");
// A coordinate no leaf origin has (origins are multiples of the leaf size): marks a free slot.
const openvdb::Coord kEmptyOrigin(1, 1, 1);
constexpr std::size_t kInitialSlots = 1024;
constexpr float kMaxIndex = 1 << 30;  // voxel coordinates (and one past them) stay within int

std::size_t hashOrigin(const openvdb::Coord& origin, std::size_t mask) {
  const auto x = static_cast<uint64_t>(static_cast<uint32_t>(origin.x() >> kLeafBits));
  const auto y = static_cast<uint64_t>(static_cast<uint32_t>(origin.y() >> kLeafBits));
  const auto z = static_cast<uint64_t>(static_cast<uint32_t>(origin.z() >> kLeafBits));
  const uint64_t h = (x * 0x9E3779B97F4A7C15ull) ^ (y * 0xC2B2AE3D27D4EB4Full) ^ (z * 0x165667B19E3779F9ull);
  return static_cast<std::size_t>(h ^ (h >> 29)) & mask;
}

openvdb::Coord leafOrigin(const openvdb::Coord& ijk) {
  return {ijk.x() & ~kLeafCoordMask, ijk.y() & ~kLeafCoordMask, ijk.z() & ~kLeafCoordMask};
}

int offsetInLeaf(const openvdb::Coord& ijk) {
  return ((ijk.x() & kLeafCoordMask) << (2 * kLeafBits)) | ((ijk.y() & kLeafCoordMask) << kLeafBits) |
         (ijk.z() & kLeafCoordMask);
}
}  // namespace

LeafCacheSampler::LeafCacheSampler(const LabeledVolume& volume)
    : inv_voxel_size_(static_cast<float>(1.0 / volume.voxelSize())),
      geometry_(volume.geometryGrid().getConstAccessor()),
      slots_(kInitialSlots, Slot{kEmptyOrigin, {}}),
      last_origin_(kEmptyOrigin) {
  if (volume.colorGrid()) {
    color_.emplace(volume.colorGrid()->getConstAccessor());
    background_luma_ = unpackLuma(volume.colorGrid()->background());
  }
}

const LeafCacheSampler::LeafPair& LeafCacheSampler::leavesAt(const openvdb::Coord& origin) {
  if (last_ && origin == last_origin_) return *last_;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t slot = hashOrigin(origin, mask);; slot = (slot + 1) & mask) {
    const Slot& s = slots_[slot];
    if (s.origin == origin) {
      last_origin_ = origin;
      last_ = &s.leaves;
      return s.leaves;
    }
    if (s.origin == kEmptyOrigin) return lookUpAndInsert(origin, slot);
  }
}

const LeafCacheSampler::LeafPair& LeafCacheSampler::lookUpAndInsert(const openvdb::Coord& origin, std::size_t slot) {
  LeafPair leaves;
  if (const GeometryLeafNode* leaf = geometry_.probeConstLeaf(origin)) leaves.geometry = leaf->buffer().data();
  if (color_)
    if (const ColorLeafNode* leaf = color_->probeConstLeaf(origin)) leaves.color = leaf->buffer().data();
  // At most half full, so that probe sequences stay short.
  if (2 * (used_ + 1) > slots_.size()) {
    grow();
    const std::size_t mask = slots_.size() - 1;
    slot = hashOrigin(origin, mask);
    while (slots_[slot].origin != kEmptyOrigin) slot = (slot + 1) & mask;
  }
  slots_[slot] = Slot{origin, leaves};
  ++used_;
  last_origin_ = origin;
  last_ = &slots_[slot].leaves;
  return *last_;
}

void LeafCacheSampler::grow() {
  std::vector<Slot> old(2 * slots_.size(), Slot{kEmptyOrigin, {}});
  old.swap(slots_);
  const std::size_t mask = slots_.size() - 1;
  for (const Slot& s : old) {
    if (s.origin == kEmptyOrigin) continue;
    std::size_t slot = hashOrigin(s.origin, mask);
    while (slots_[slot].origin != kEmptyOrigin) slot = (slot + 1) & mask;
    slots_[slot] = s;
  }
  last_ = nullptr;  // pointed into the old table
}

bool LeafCacheSampler::gatherCell(const openvdb::Coord& base, float tsdf[8], float* luma) {
  PackedVoxel corners[8];
  const PackedColor* color_values[8];
  // Two thirds of the cells lie wholly in one leaf: one probe, then the corners' fixed offsets.
  if ((base.x() & kLeafCoordMask) != kLeafCoordMask && (base.y() & kLeafCoordMask) != kLeafCoordMask &&
      (base.z() & kLeafCoordMask) != kLeafCoordMask) {
    const LeafPair& leaves = leavesAt(leafOrigin(base));
    if (!leaves.geometry) return false;
    const int offset = offsetInLeaf(base);
    for (int i = 0; i < 8; ++i) {
      corners[i] = leaves.geometry[offset + kCellCornerOffsets[i]];
      if (!isObserved(corners[i])) return false;
      color_values[i] = leaves.color ? leaves.color + offset + kCellCornerOffsets[i] : nullptr;
    }
  } else {
    for (int i = 0; i < 8; ++i) {
      const openvdb::Coord ijk = base.offsetBy(i & 1, (i >> 1) & 1, (i >> 2) & 1);
      const LeafPair& leaves = leavesAt(leafOrigin(ijk));
      if (!leaves.geometry) return false;
      const int offset = offsetInLeaf(ijk);
      corners[i] = leaves.geometry[offset];
      if (!isObserved(corners[i])) return false;
      color_values[i] = leaves.color ? leaves.color + offset : nullptr;
    }
  }
  for (int i = 0; i < 8; ++i) tsdf[i] = unpackTsdf(corners[i]);
  if (luma)
    for (int i = 0; i < 8; ++i) luma[i] = color_values[i] ? unpackLuma(*color_values[i]) : background_luma_;
  return true;
}

bool LeafCacheSampler::cellAt(const Eigen::Vector3f& world, openvdb::Coord& base, Eigen::Vector3f& fraction) const {
  const Eigen::Vector3f index = world * inv_voxel_size_;
  // Beyond any voxel's integer coordinates, or not finite (NaN fails every comparison).
  if (!(std::abs(index.x()) < kMaxIndex && std::abs(index.y()) < kMaxIndex && std::abs(index.z()) < kMaxIndex))
    return false;
  base = openvdb::Coord(static_cast<int>(std::floor(index.x())), static_cast<int>(std::floor(index.y())),
                        static_cast<int>(std::floor(index.z())));
  fraction =
      index - Eigen::Vector3f(static_cast<float>(base.x()), static_cast<float>(base.y()), static_cast<float>(base.z()));
  return true;
}

bool LeafCacheSampler::tsdfAndGradient(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& gradient) {
  openvdb::Coord base;
  Eigen::Vector3f f;
  float v[8];
  if (!cellAt(world, base, f) || !gatherCell(base, v, nullptr)) return false;
  tsdf = trilinearWithGradient(v, f.x(), f.y(), f.z(), gradient);
  gradient *= inv_voxel_size_;
  return true;
}

bool LeafCacheSampler::tsdfAndIntensity(const Eigen::Vector3f& world, float& tsdf, Eigen::Vector3f& tsdf_gradient,
                                        float& intensity, Eigen::Vector3f& intensity_gradient, bool& has_intensity) {
  openvdb::Coord base;
  Eigen::Vector3f f;
  float v[8];
  float luma[8];
  const bool with_color = color_.has_value();
  if (!cellAt(world, base, f) || !gatherCell(base, v, with_color ? luma : nullptr)) return false;
  tsdf = trilinearWithGradient(v, f.x(), f.y(), f.z(), tsdf_gradient);
  tsdf_gradient *= inv_voxel_size_;
  has_intensity = with_color;
  if (with_color) {
    intensity = trilinearWithGradient(luma, f.x(), f.y(), f.z(), intensity_gradient);
    intensity_gradient *= inv_voxel_size_;
  }
  return true;
}

}  // namespace semfuse::volume
