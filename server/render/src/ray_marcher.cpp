#include "ray_marcher.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace semfuse::render::detail {
namespace {

using volume::PackedVoxel;
using GeometryTree = volume::GeometryGrid::TreeType;
using LeafNode = GeometryTree::LeafNodeType;
using UpperNode = GeometryTree::RootNodeType::ChildNodeType;  // 32^3 lower nodes
using LowerNode = UpperNode::ChildNodeType;                   // 16^3 leaves

constexpr int kLeafDim = LeafNode::DIM;
constexpr int kLeafMask = kLeafDim - 1;
static_assert(kLeafDim == 8, "the mask tests below assume 8^3 leaves: one 64-bit mask word per x slice");

// Step as a fraction of the TSDF value in front of the surface. The stored TSDF is measured along
// the integrating cameras' rays, so it can exceed the true distance; stepping a little less than
// it keeps the next sample inside the negative band behind the surface instead of past it.
constexpr double kTsdfStepFraction = 0.8;
// Smallest step, in voxels: where the TSDF is unknown (some corner unobserved) or tiny.
constexpr double kMinStepVoxels = 0.5;
constexpr int kRefineIterations = 2;
// Pushes a ray that was moved onto a block's face into the next block (voxels).
constexpr double kFaceNudgeVoxels = 1e-3;

// Offsets of the 8 cell corners inside one leaf buffer, corner = dx + 2 dy + 4 dz.
// OpenVDB leaves store z fastest: offset = x * 64 + y * 8 + z.
constexpr int kCornerOffsets[8] = {0, 64, 8, 72, 1, 65, 9, 73};

// floor() for the index range of a grid; std::floor is a library call without SSE4.1, and it
// sits in the innermost loop.
int floorInt(double x) {
  const int i = static_cast<int>(x);
  return i - (x < i);
}
openvdb::Coord floorCoord(const Eigen::Vector3d& p) { return {floorInt(p.x()), floorInt(p.y()), floorInt(p.z())}; }

// Edge, in voxels, of the empty region a value found at tree depth `depth` stands for (depth as
// ValueAccessor::getValueDepth: -1 background outside every root entry, 0 root tile, 1 tile of an
// upper internal node, 2 tile of a lower internal node, 3 leaf).
int unallocatedRegionDim(int depth) {
  switch (depth) {
    case -1:
    case 0: return UpperNode::DIM;
    case 1: return LowerNode::DIM;
    case 2: return LeafNode::DIM;
    default: return 0;  // a leaf: nothing to skip at this level
  }
}

// Where a lower internal node has no leaf at `ijk`: edge, in voxels, of the largest aligned block
// of 4^3 or 2^3 leaf slots around it that are all empty (tiles), else one leaf. Child slot
// (x, y, z) of the 16^3 node is bit x * 256 + y * 16 + z of its child mask.
int emptyLeafBlockDim(const LowerNode& node, const openvdb::Coord& ijk) {
  static_assert(LowerNode::DIM == 128, "the child-mask test assumes 16^3 leaf slots");
  const auto& children = node.getChildMask();
  const int x = (ijk.x() & 127) >> 3, y = (ijk.y() & 127) >> 3, z = (ijk.z() & 127) >> 3;
  for (int dim = 4; dim >= 2; dim >>= 1) {
    const int x0 = x & ~(dim - 1), y0 = y & ~(dim - 1), z0 = z & ~(dim - 1);
    // Slab x holds 4 words of 4 y rows each; one y row is 16 bits, z fastest.
    bool empty = true;
    for (int i = x0; i < x0 + dim && empty; ++i)
      for (int j = y0; j < y0 + dim && empty; ++j) {
        const openvdb::Index bit = static_cast<openvdb::Index>(i * 256 + j * 16 + z0);
        const uint64_t word = children.getWord<uint64_t>(bit >> 6);
        empty = ((word >> (bit & 63)) & ((uint64_t{1} << dim) - 1)) == 0;
      }
    if (empty) return dim * LeafNode::DIM;
  }
  return LeafNode::DIM;
}

// Edge of the largest aligned block (8, 4, 2 or 1 voxels) around `ijk` in which the leaf holds
// no active voxel, 0 when voxel `ijk` itself is active. Inactive voxels are never observed (the
// integrator activates every voxel it writes), and a sample whose base voxel is unobserved is
// invalid, so a ray may jump to the block's exit without missing a valid sample.
int unobservedBlockDim(const LeafNode& leaf, const openvdb::Coord& ijk) {
  const auto& mask = leaf.getValueMask();
  const int x = ijk.x() & kLeafMask, y = ijk.y() & kLeafMask, z = ijk.z() & kLeafMask;
  if (mask.isOn(static_cast<openvdb::Index32>((x << 6) | (y << 3) | z))) return 0;
  if (mask.isOff()) return 8;
  // Word x holds the yz slice at that x, bit y * 8 + z. The dim x dim square at (y0, z0) is
  // `dim` runs of `dim` bits, one per y row.
  for (int dim = 4; dim >= 2; dim >>= 1) {
    const int x0 = x & ~(dim - 1), y0 = y & ~(dim - 1), z0 = z & ~(dim - 1);
    const uint64_t row = (uint64_t{1} << dim) - 1;
    const uint64_t rows = dim == 4 ? 0x01010101ull : 0x0101ull;
    const uint64_t square = (row * rows) << (y0 * 8 + z0);
    uint64_t any = 0;
    for (int i = x0; i < x0 + dim; ++i) any |= mask.getWord<uint64_t>(static_cast<openvdb::Index>(i));
    if ((any & square) == 0) return dim;
  }
  return 1;
}

// Ray parameter where o + t d leaves the aligned cube of edge `dim` that holds voxel `ijk`;
// inv_d = 1 / d per axis (infinite along an axis the ray does not move on), computed once per
// ray so that a skip multiplies instead of dividing.
double exitOfBlock(const openvdb::Coord& ijk, int dim, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                   const Eigen::Vector3d& inv_d) {
  double t_exit = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (d[axis] == 0.0) continue;
    const int lo = ijk[axis] & ~(dim - 1);
    const double face = d[axis] > 0.0 ? lo + dim : lo;
    t_exit = std::min(t_exit, (face - o[axis]) * inv_d[axis]);
  }
  return t_exit;
}

}  // namespace

RayMarcher::RayMarcher(const volume::LabeledVolume& volume, bool skip_empty_space)
    : accessor_(volume.geometryGrid().getConstAccessor()),
      inv_voxel_size_(1.0 / volume.voxelSize()),
      skip_empty_space_(skip_empty_space) {}

bool RayMarcher::gatherCorners(const LeafView& view, const openvdb::Coord& base, PackedVoxel corners[8]) {
  // Most cells lie inside one leaf: read its buffer directly. Others cross into neighbouring
  // leaves, which the accessor's cache usually still holds.
  if (view.values && (base.x() & kLeafMask) != kLeafMask && (base.y() & kLeafMask) != kLeafMask &&
      (base.z() & kLeafMask) != kLeafMask) {
    const PackedVoxel* values = view.values + LeafNode::coordToOffset(base);
    for (int i = 0; i < 8; ++i) {
      corners[i] = values[kCornerOffsets[i]];
      if (!volume::isObserved(corners[i])) return false;
    }
    return true;
  }
  for (int i = 0; i < 8; ++i) {
    corners[i] = accessor_.getValue(base.offsetBy(i & 1, (i >> 1) & 1, i >> 2));
    if (!volume::isObserved(corners[i])) return false;
  }
  return true;
}

bool RayMarcher::sampleAt(const LeafView& view, const openvdb::Coord& base, const Eigen::Vector3d& index,
                          float& tsdf_voxels) {
  PackedVoxel corners[8];
  if (!gatherCorners(view, base, corners)) return false;
  float v[8];
  for (int i = 0; i < 8; ++i) v[i] = volume::unpackTsdf(corners[i]);
  const auto fx = static_cast<float>(index.x() - base.x()), fy = static_cast<float>(index.y() - base.y()),
             fz = static_cast<float>(index.z() - base.z());
  const float a00 = v[0] + (v[1] - v[0]) * fx, a10 = v[2] + (v[3] - v[2]) * fx;
  const float a01 = v[4] + (v[5] - v[4]) * fx, a11 = v[6] + (v[7] - v[6]) * fx;
  const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
  tsdf_voxels = (b0 + (b1 - b0) * fz) * static_cast<float>(inv_voxel_size_);
  return true;
}

bool RayMarcher::sample(const Eigen::Vector3d& index, float& tsdf_voxels) {
  const openvdb::Coord base = floorCoord(index);
  LeafView view;
  enterLeaf(base, view);
  return sampleAt(view, base, index, tsdf_voxels);
}

bool RayMarcher::findSurface(const MarchRay& ray, double& t_surface) {
  // The ray in index space, once: t keeps its meaning (camera depth).
  const Eigen::Vector3d o = ray.origin * inv_voxel_size_;
  const Eigen::Vector3d d = ray.direction * inv_voxel_size_;
  const Eigen::Vector3d inv_d = d.cwiseInverse();
  const double voxels_per_t = d.norm();
  const double t_per_voxel = 1.0 / voxels_per_t;
  const double min_step = kMinStepVoxels * t_per_voxel;
  const double nudge = kFaceNudgeVoxels * t_per_voxel;
  const double tsdf_step_scale = kTsdfStepFraction * t_per_voxel;

  bool have_positive = false;  // previous sample valid and in front of a surface
  double t_prev = 0.0;
  float f_prev = 0.0f;
  double t = ray.t_min;
  LeafView view;
  while (t < ray.t_max) {
    const Eigen::Vector3d x = o + t * d;
    const openvdb::Coord base = floorCoord(x);
    enterLeaf(base, view);
    const Leaf* leaf = view.leaf;
    if (skip_empty_space_) {
      int skip;
      if (leaf) {
        skip = unobservedBlockDim(*leaf, base);
      } else {
        skip = unallocatedRegionDim(accessor_.getValueDepth(base));
        if (skip == LeafNode::DIM)  // a missing leaf: its neighbours may be missing too
          if (const LowerNode* node = accessor_.probeConstNode<LowerNode>(base)) skip = emptyLeafBlockDim(*node, base);
      }
      if (skip > 0) {
        t = std::max(t, exitOfBlock(base, skip, o, d, inv_d)) + nudge;
        have_positive = false;
        continue;
      }
    }
    float f;
    if (!sampleAt(view, base, x, f)) {
      // Every point of this cell reads the same 8 corners, so none of them gives a valid sample:
      // with skipping on, leave the cell instead of stepping half a voxel.
      have_positive = false;
      t = skip_empty_space_ ? std::max(t, exitOfBlock(base, 1, o, d, inv_d)) + nudge : t + min_step;
      continue;
    }
    if (f <= 0.0f && have_positive) {
      // Regula falsi on the trilinear interpolant between the bracketing samples.
      double t_pos = t_prev, t_neg = t;
      float f_pos = f_prev, f_neg = f;
      auto secant = [&] { return t_pos + (t_neg - t_pos) * f_pos / static_cast<double>(f_pos - f_neg); };
      for (int i = 0; i < kRefineIterations && f_pos - f_neg > 0.0f; ++i) {
        const double t_mid = secant();
        float f_mid;
        if (!sample(o + t_mid * d, f_mid)) break;
        if (f_mid > 0.0f) {
          t_pos = t_mid;
          f_pos = f_mid;
        } else {
          t_neg = t_mid;
          f_neg = f_mid;
        }
      }
      t_surface = f_pos - f_neg > 0.0f ? secant() : t_neg;
      return true;
    }
    have_positive = f > 0.0f;
    t_prev = t;
    f_prev = f;
    t += f > 0.0f ? std::max(min_step, tsdf_step_scale * f) : min_step;
  }
  return false;
}

}  // namespace semfuse::render::detail
