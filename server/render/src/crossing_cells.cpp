#include "crossing_cells.hpp"

#include <algorithm>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include "semfuse/render/raycast.hpp"
#include "voxel_columns.hpp"

namespace semfuse::render::detail {
namespace {

using Leaf = CrossingCells::Leaf;

// A half-space through the camera centre (or parallel to the image plane) in camera coordinates:
// n . p + offset >= 0 inside.
struct Plane {
  Eigen::Vector3d n;
  double offset;
};

// The planes bounding what the rays of the image can reach: the four sides one pixel outside the
// outermost pixel centres, and the depth range widened by a voxel.
std::array<Plane, 6> frustumPlanes(const PinholeIntrinsics& k, double min_depth, double max_depth, double margin) {
  return {{
      {{k.fx, 0.0, k.cx + 1.0}, 0.0},            // u >= -1
      {{-k.fx, 0.0, k.width - k.cx}, 0.0},       // u <= width
      {{0.0, k.fy, k.cy + 1.0}, 0.0},            // v >= -1
      {{0.0, -k.fy, k.height - k.cy}, 0.0},      // v <= height
      {{0.0, 0.0, 1.0}, -(min_depth - margin)},  // z >= min_depth
      {{0.0, 0.0, -1.0}, max_depth + margin},    // z <= max_depth
  }};
}

// False only when all 8 corners of the leaf's cell box lie outside one plane: then no point of
// the box, and so no ray sample in it, is inside the frustum.
bool meetsFrustum(const openvdb::Coord& origin, double voxel, const Eigen::Matrix3d& world_to_camera,
                  const Eigen::Vector3d& camera_origin, const std::array<Plane, 6>& planes) {
  const Eigen::Vector3d low =
      world_to_camera * (Eigen::Vector3d(origin.x(), origin.y(), origin.z()) * voxel - camera_origin);
  const double edge = CrossingCells::kLeafDim * voxel;
  const Eigen::Vector3d ex = world_to_camera.col(0) * edge, ey = world_to_camera.col(1) * edge,
                        ez = world_to_camera.col(2) * edge;
  for (const Plane& plane : planes) {
    bool all_outside = true;
    for (int c = 0; c < 8 && all_outside; ++c) {
      Eigen::Vector3d p = low;
      if (c & 1) p += ex;
      if (c & 2) p += ey;
      if (c & 4) p += ez;
      all_outside = plane.n.dot(p) + plane.offset < 0.0;
    }
    if (all_outside) return false;
  }
  return true;
}

// The crossing cells of one leaf, from its voxel columns (bit z = voxel z, 0..8; see
// voxel_columns.hpp): per cell, AND the observed bits of its 4 columns and 2 levels, OR their
// non-positive and positive bits.
std::array<uint64_t, CrossingCells::kLeafDim> crossingMask(const VoxelColumns& c) {
  std::array<uint64_t, CrossingCells::kLeafDim> mask{};
  for (int x = 0; x < CrossingCells::kLeafDim; ++x)
    for (int y = 0; y < CrossingCells::kLeafDim; ++y) {
      const unsigned all_seen =
          c.observed[x][y] & c.observed[x + 1][y] & c.observed[x][y + 1] & c.observed[x + 1][y + 1];
      const unsigned any_below =
          c.non_positive[x][y] | c.non_positive[x + 1][y] | c.non_positive[x][y + 1] | c.non_positive[x + 1][y + 1];
      const unsigned any_above =
          c.positive[x][y] | c.positive[x + 1][y] | c.positive[x][y + 1] | c.positive[x + 1][y + 1];
      // Bit z of each: voxels z and z + 1 of the columns, the cell's two levels.
      const unsigned cells =
          (all_seen & (all_seen >> 1)) & (any_below | (any_below >> 1)) & (any_above | (any_above >> 1)) & 0xFFu;
      mask[x] |= static_cast<uint64_t>(cells) << (CrossingCells::kLeafDim * y);
    }
  return mask;
}

// Fills the coarse block masks of a leaf from its cell mask.
void summarizeBlocks(CrossingCells::LeafCells& leaf) {
  leaf.blocks2 = 0;
  leaf.blocks4 = 0;
  for (int x = 0; x < CrossingCells::kLeafDim; ++x) {
    const uint64_t word = leaf.crossing[x];
    if (word == 0) continue;
    for (int by = 0; by < 4; ++by)
      for (int bz = 0; bz < 4; ++bz) {
        // Cells y = 2 by, 2 by + 1 and z = 2 bz, 2 bz + 1 of slice x: bits 8 y + z.
        if (!(word & (uint64_t{0x0303} << (16 * by + 2 * bz)))) continue;
        leaf.blocks2 |= uint64_t{1} << (((x >> 1) << 4) | (by << 2) | bz);
        leaf.blocks4 |= static_cast<uint8_t>(1u << (((x >> 2) << 2) | ((by >> 1) << 1) | (bz >> 1)));
      }
  }
}

// Surface boxes are widened by this much (voxels) on every side.
constexpr float kBoxMarginVoxels = 0.01f;
// And their half-spaces by this much TSDF (metres): boxes and half-spaces are float arithmetic.
constexpr float kPlaneMarginTsdf = 1e-5f;

// The part of [0, 1] where the linear interpolant from a (at 0) to b (at 1) is <= 0, for the 4
// edges of a cell along one axis at once (4 float lanes): [lo, hi], empty (lo > hi) when none.
void nonPositiveSpan(const Eigen::Array4f& a, const Eigen::Array4f& b, float& lo, float& hi) {
  constexpr float kInfF = std::numeric_limits<float>::infinity();
  const Eigen::Array4f crossing = a / (a - b);  // used only where the signs differ (then a != b)
  const auto a_below = a <= 0.0f, b_below = b <= 0.0f;
  lo = a_below.select(Eigen::Array4f::Zero(), b_below.select(crossing, Eigen::Array4f::Constant(kInfF))).minCoeff();
  hi = b_below.select(Eigen::Array4f::Ones(), a_below.select(crossing, Eigen::Array4f::Constant(-kInfF))).maxCoeff();
}

// Per axis, the corners k = dx + 2 dy + 4 dz of a cell's face at 0 along it (as a mask and as a
// list); the face at 1 holds the same corners plus that axis' bit.
constexpr unsigned kLowerFace[3] = {0x55u, 0x33u, 0x0Fu};
constexpr int kLowerFaceCorners[3][4] = {{0, 2, 4, 6}, {0, 1, 4, 5}, {0, 1, 2, 3}};
// Brick offset of corner k from the cell's base voxel.
constexpr int kCornerOffset[8] = {0,
                                  CrossingCells::kBrickStride,
                                  CrossingCells::kBrickDim,
                                  CrossingCells::kBrickStride + CrossingCells::kBrickDim,
                                  1,
                                  CrossingCells::kBrickStride + 1,
                                  CrossingCells::kBrickDim + 1,
                                  CrossingCells::kBrickStride + CrossingCells::kBrickDim + 1};

// The box and half-space of the non-positive points of the crossing cells in the 2^3 block at
// leaf-local (x0, y0, z0) (which holds at least one), leaf-local. The box: in a cell, the
// trilinear TSDF on the slice at a fixed position along one axis is bilinear in the other two, so
// its least value lies on one of the 4 cell edges along that axis, and the slice holds a
// non-positive point only where one of those edges is non-positive. So, per axis, the
// non-positive points of the cell lie within the union of the non-positive spans of its 4 edges
// along that axis: a box much thinner than the cell where the surface runs close to a voxel
// plane. The half-space: see below.
SurfaceBox surfaceBox(const CrossingCells::LeafCells& leaf, const VoxelColumns& columns, int x0, int y0, int z0) {
  constexpr int kBlockDim = CrossingCells::kSurfaceBlockDim;
  constexpr int kBlockCells = kBlockDim * kBlockDim * kBlockDim;
  using Corners = Eigen::Array<float, 8, 1>;  // of one cell, k = dx + 2 dy + 4 dz
  SurfaceBox box;
  Corners corners[kBlockCells];  // of the block's crossing cells
  int cell_at[kBlockCells][3];
  int cells = 0;
  float edge_sum[3] = {0.0f, 0.0f, 0.0f};  // summed differences along the cells' edges, per axis
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::numeric_limits<float>::infinity();
    box.hi[a] = -box.lo[a];
  }
  for (int x = x0; x < x0 + kBlockDim; ++x)
    for (int y = y0; y < y0 + kBlockDim; ++y)
      for (int z = z0; z < z0 + kBlockDim; ++z) {
        if (!leaf.isCrossing(x, y, z)) continue;
        // Which corners are <= 0, from the column bits (all 8 are observed).
        const unsigned c00 = columns.non_positive[x][y] >> z, c10 = columns.non_positive[x + 1][y] >> z,
                       c01 = columns.non_positive[x][y + 1] >> z, c11 = columns.non_positive[x + 1][y + 1] >> z;
        const unsigned below = (c00 & 1u) | (c10 & 1u) << 1 | (c01 & 1u) << 2 | (c11 & 1u) << 3 | (c00 & 2u) << 3 |
                               (c10 & 2u) << 4 | (c01 & 2u) << 5 | (c11 & 2u) << 6;
        const float* c = leaf.tsdf + kCornerOffset[1] * x + kCornerOffset[2] * y + z;
        Corners& v = corners[cells];
        for (int k = 0; k < 8; ++k) v[k] = c[kCornerOffset[k]];
        const int cell[3] = {x, y, z};
        for (int axis = 0; axis < 3; ++axis) cell_at[cells][axis] = cell[axis];
        ++cells;
        edge_sum[0] += (v[1] + v[3] + v[5] + v[7]) - (v[0] + v[2] + v[4] + v[6]);
        edge_sum[1] += (v[2] + v[3] + v[6] + v[7]) - (v[0] + v[1] + v[4] + v[5]);
        edge_sum[2] += (v[4] + v[5] + v[6] + v[7]) - (v[0] + v[1] + v[2] + v[3]);
        for (int axis = 0; axis < 3; ++axis) {
          float lo = 0.0f, hi = 1.0f;
          // Most often both faces across the axis have a non-positive corner: the whole span,
          // with no division.
          if (!(below & kLowerFace[axis]) || !(below & ~kLowerFace[axis] & 0xFFu)) {
            const int* lower = kLowerFaceCorners[axis];
            const int along = 1 << axis;
            nonPositiveSpan(
                Eigen::Array4f(v[lower[0]], v[lower[1]], v[lower[2]], v[lower[3]]),
                Eigen::Array4f(v[lower[0] | along], v[lower[1] | along], v[lower[2] | along], v[lower[3] | along]), lo,
                hi);
          }
          box.lo[axis] = std::min(box.lo[axis], cell[axis] + lo);
          box.hi[axis] = std::max(box.hi[axis], cell[axis] + hi);
        }
      }
  // The half-space. Any linear L(p) = g . p will do: in a cell, f - L is trilinear too, so it is
  // no less than its least corner value, and f(p) <= 0 implies L(p) <= max over the corners of
  // (L - f). Over the block's crossing cells that gives g . p <= offset. The closer g follows the
  // TSDF's gradient, the closer that plane lies to the surface: g is the mean difference along
  // the cells' edges. The maximum is taken per corner k across the cells (8 lanes side by side:
  // a chain as long as the number of cells, not 8 times that).
  float g[3];
  for (int a = 0; a < 3; ++a) g[a] = edge_sum[a] / static_cast<float>(4 * cells);
  static const Corners kDx = (Corners() << 0, 1, 0, 1, 0, 1, 0, 1).finished();
  static const Corners kDy = (Corners() << 0, 0, 1, 1, 0, 0, 1, 1).finished();
  static const Corners kDz = (Corners() << 0, 0, 0, 0, 1, 1, 1, 1).finished();
  const Corners g_at_corner = g[0] * kDx + g[1] * kDy + g[2] * kDz;  // g . (corner - base voxel)
  Corners highest = Corners::Constant(-std::numeric_limits<float>::infinity());
  for (int i = 0; i < cells; ++i) {
    const float at_base = g[0] * cell_at[i][0] + g[1] * cell_at[i][1] + g[2] * cell_at[i][2];
    highest = highest.max((at_base + g_at_corner) - corners[i]);
  }
  for (int a = 0; a < 3; ++a) box.normal[a] = g[a];
  box.offset = highest.maxCoeff();
  return box;
}

// The surface boxes of a leaf (crossing masks and brick done, `columns` its voxel columns), in
// index space, onto `out`.
void addSurfaceBoxes(const CrossingCells::LeafCells& leaf, const VoxelColumns& columns, std::vector<SurfaceBox>& out) {
  static_assert(CrossingCells::kSurfaceBlockDim == 2, "blocks2 has one bit per 2^3 block");
  for (uint64_t blocks = leaf.blocks2; blocks != 0; blocks &= blocks - 1) {
    const int bit = __builtin_ctzll(blocks);  // 16 bx + 4 by + bz
    SurfaceBox box = surfaceBox(leaf, columns, 2 * (bit >> 4), 2 * ((bit >> 2) & 3), 2 * (bit & 3));
    // A hair wider: the box came from rounded float arithmetic.
    for (int a = 0; a < 3; ++a) {
      box.lo[a] += static_cast<float>(leaf.origin[a]) - kBoxMarginVoxels;
      box.hi[a] += static_cast<float>(leaf.origin[a]) + kBoxMarginVoxels;
    }
    // From leaf-local to index space, and as much wider as the box (the gradient is at most
    // the largest TSDF difference along an edge).
    box.offset += box.normal[0] * leaf.origin.x() + box.normal[1] * leaf.origin.y() + box.normal[2] * leaf.origin.z() +
                  kBoxMarginVoxels * (std::abs(box.normal[0]) + std::abs(box.normal[1]) + std::abs(box.normal[2])) +
                  kPlaneMarginTsdf;
    out.push_back(box);
  }
}

}  // namespace

CrossingCells::CrossingCells(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                             const Pose& camera_to_world, double min_depth, double max_depth, Options options) {
  std::vector<const Leaf*> leaves;
  leaves.reserve(volume.geometryGrid().tree().leafCount());
  volume.geometryGrid().tree().getNodes(leaves);
  leaves_.resize(leaves.size());
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    leaves_[i].origin = leaves[i]->origin();
    leaves_[i].voxels = leaves[i]->buffer().data();
  }

  index_ = LeafIndex(leaves_.size(), [&](std::size_t i) { return leaves_[i].origin; });

  const double voxel = volume.voxelSize();
  const Eigen::Matrix3d world_to_camera = camera_to_world.linear().transpose();
  const Eigen::Vector3d camera_origin = camera_to_world.translation();
  const auto planes = frustumPlanes(k, min_depth, max_depth, voxel);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves_.size(), 64), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i)
      leaves_[i].in_view =
          !leaves[i]->isEmpty() && meetsFrustum(leaves_[i].origin, voxel, world_to_camera, camera_origin, planes);
  });
  // The leaves rays can read: those in view and their upper neighbours (cells on a leaf's upper
  // faces read those), each leaf in view with its 8 (itself first), looked up once.
  std::vector<uint32_t> needed;
  std::vector<uint8_t> is_needed(leaves_.size(), 0);
  std::vector<std::array<uint32_t, 8>> upper_of;  // per leaf in view, in leaf order; kNone where unallocated
  for (std::size_t i = 0; i < leaves_.size(); ++i) {
    if (!leaves_[i].in_view) continue;
    std::array<uint32_t, 8>& upper = upper_of.emplace_back();
    for (int n = 0; n < 8; ++n) {
      const CrossingCells::LeafCells* neighbour =
          find(leaves_[i].origin.offsetBy((n & 1) * CrossingCells::kLeafDim, ((n >> 1) & 1) * CrossingCells::kLeafDim,
                                          (n >> 2) * CrossingCells::kLeafDim));
      upper[n] = neighbour ? static_cast<uint32_t>(neighbour - leaves_.data()) : LeafIndex::kNone;
      if (!neighbour || is_needed[upper[n]]) continue;
      needed.push_back(upper[n]);
      is_needed[upper[n]] = 1;
    }
  }
  std::vector<const volume::ColorGrid::TreeType::LeafNodeType*> color_leaves;
  if (options.with_color && volume.colorGrid()) {
    color_leaves.assign(leaves_.size(), nullptr);
    const auto& color_tree = volume.colorGrid()->tree();
    for (uint32_t j : needed) color_leaves[j] = color_tree.probeConstLeaf(leaves_[j].origin);
  }
  if (options.copy_voxels) {
    // Copies of just those leaves, so that the rays can run after the volume has changed.
    // Left uninitialised (every voxel is copied over, and a colour copy is only pointed at once
    // written): zeroing ~20 MB first would add a pass to what runs under the server's lock.
    voxel_copies_.reset(new volume::PackedVoxel[needed.size() * Leaf::SIZE]);
    if (!color_leaves.empty()) color_copies_.reset(new volume::PackedColor[needed.size() * Leaf::SIZE]);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, needed.size(), 64), [&](const auto& range) {
      for (std::size_t c = range.begin(); c < range.end(); ++c) {
        CrossingCells::LeafCells& leaf = leaves_[needed[c]];
        volume::PackedVoxel* copy = voxel_copies_.get() + c * Leaf::SIZE;
        std::copy(leaf.voxels, leaf.voxels + Leaf::SIZE, copy);
        leaf.voxels = copy;
        if (const auto* color = color_leaves.empty() ? nullptr : color_leaves[needed[c]]) {
          volume::PackedColor* color_copy = color_copies_.get() + c * Leaf::SIZE;
          std::copy(color->buffer().data(), color->buffer().data() + Leaf::SIZE, color_copy);
          leaf.colors = color_copy;
        }
      }
    });
    for (std::size_t i = 0; i < leaves_.size(); ++i)
      if (!is_needed[i]) leaves_[i].voxels = nullptr;  // never read; the copy does not outlive the volume's leaves
  } else if (!color_leaves.empty()) {
    for (uint32_t j : needed)
      if (color_leaves[j]) leaves_[j].colors = color_leaves[j]->buffer().data();
  }
  auto upper = upper_of.begin();
  for (CrossingCells::LeafCells& leaf : leaves_) {
    if (!leaf.in_view) continue;
    for (int n = 0; n < 8; ++n) {
      const CrossingCells::LeafCells* neighbour = (*upper)[n] == LeafIndex::kNone ? nullptr : &leaves_[(*upper)[n]];
      leaf.upper[n] = neighbour ? neighbour->voxels : nullptr;
      leaf.upper_colors[n] = neighbour ? neighbour->colors : nullptr;
    }
    ++upper;
  }
}

void CrossingCells::findCrossings() {
  // A brick per leaf in view, numbered in leaf order.
  std::vector<uint32_t> brick_of(leaves_.size(), 0);
  uint32_t bricks = 0;
  for (std::size_t i = 0; i < leaves_.size(); ++i)
    if (leaves_[i].in_view) brick_of[i] = bricks++;
  bricks_.reset(new float[static_cast<std::size_t>(bricks) * kBrickSize]);
  const auto read_columns = raycastKernel() == RaycastKernel::kAvx2 ? &readVoxelColumnsAvx2 : &readVoxelColumns;
  // The surface boxes are found right after each brick is written, while it is in cache.
  tbb::enumerable_thread_specific<std::vector<SurfaceBox>> boxes;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, leaves_.size(), 64), [&](const auto& range) {
    VoxelColumns columns;
    std::vector<SurfaceBox>& leaf_boxes = boxes.local();
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      CrossingCells::LeafCells& leaf = leaves_[i];
      if (!leaf.in_view) continue;
      float* brick = bricks_.get() + static_cast<std::size_t>(brick_of[i]) * kBrickSize;
      read_columns(leaf, brick, columns);
      leaf.crossing = crossingMask(columns);
      leaf.tsdf = brick;
      summarizeBlocks(leaf);
      addSurfaceBoxes(leaf, columns, leaf_boxes);
    }
  });
  surface_boxes_.clear();
  for (const auto& part : boxes) surface_boxes_.insert(surface_boxes_.end(), part.begin(), part.end());
}

}  // namespace semfuse::render::detail
