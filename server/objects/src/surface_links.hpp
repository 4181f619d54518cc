#pragma once
// Internal: the neighbour pairs ("links") of the surface that grouping and id matching look at:
// surface voxels within one voxel of each other (the 26-neighbourhood), and two apart along an
// axis, which bridges a gap of one voxel (a hole, or a voxel of another label).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>
#include <Eigen/Core>

#include "semfuse/objects/surface_voxels.hpp"

namespace semfuse::objects::detail {

struct LinkOffset {
  int dx, dy, dz;
  Eigen::Vector3f direction;  // unit
  Eigen::Vector3f offset;     // (dx, dy, dz)
};

inline constexpr std::size_t kLinkOffsets = 16;

// Half of the symmetric neighbourhood, so that every unordered pair is visited once.
inline const std::array<LinkOffset, kLinkOffsets>& linkOffsets() {
  static const std::array<LinkOffset, kLinkOffsets> offsets = [] {
    std::array<LinkOffset, kLinkOffsets> out{};
    std::size_t k = 0;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const bool forward = dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dx > 0)));
          const Eigen::Vector3f offset{static_cast<float>(dx), static_cast<float>(dy), static_cast<float>(dz)};
          if (forward) out[k++] = {dx, dy, dz, offset.normalized(), offset};
        }
    out[k++] = {2, 0, 0, Eigen::Vector3f::UnitX(), 2.0f * Eigen::Vector3f::UnitX()};
    out[k++] = {0, 2, 0, Eigen::Vector3f::UnitY(), 2.0f * Eigen::Vector3f::UnitY()};
    out[k++] = {0, 0, 2, Eigen::Vector3f::UnitZ(), 2.0f * Eigen::Vector3f::UnitZ()};
    return out;
  }();
  return offsets;
}

// Surface voxels p and q = p + linkOffsets()[k].
struct Link {
  int32_t p, q;
  uint8_t k;
};

// Visits the links leaf by leaf, every lookup an array read in the leaf or one of its neighbours.
class SurfaceLinks {
 public:
  using IndexLeaf = openvdb::Int32Tree::LeafNodeType;
  static constexpr int kDim = static_cast<int>(IndexLeaf::DIM);

  explicit SurfaceLinks(const SurfaceVoxels& surface) : tree_(surface.indexTree()) {
    leaves_.reserve(tree_.leafCount());
    tree_.getNodes(leaves_);
  }

  std::size_t leafCount() const { return leaves_.size(); }

  // fn(p, q, k): surface voxels p and q = p + linkOffsets()[k], p in the given leaf.
  template <class Fn>
  void forEachInLeaf(std::size_t leaf_index, Fn&& fn) const {
    const IndexLeaf& leaf = *leaves_[leaf_index];
    // Value buffers of the 3x3x3 leaves around this one (nullptr where none), by (lx, ly, lz) + 1.
    std::array<const int32_t*, 27> around{};
    const openvdb::Coord origin = leaf.origin();
    for (int lz = -1; lz <= 1; ++lz)
      for (int ly = -1; ly <= 1; ++ly)
        for (int lx = -1; lx <= 1; ++lx) {
          const IndexLeaf* n =
              (lx | ly | lz) == 0 ? &leaf : tree_.probeConstLeaf(origin.offsetBy(lx * kDim, ly * kDim, lz * kDim));
          around[(lx + 1) + 3 * (ly + 1) + 9 * (lz + 1)] = n ? n->buffer().data() : nullptr;
        }
    const auto& offsets = linkOffsets();
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
      const int32_t p = *it;
      const openvdb::Index n = it.pos();
      const int x = int(n >> 6), y = int((n >> 3) & 7), z = int(n & 7);
      for (std::size_t k = 0; k < kLinkOffsets; ++k) {
        const int nx = x + offsets[k].dx, ny = y + offsets[k].dy, nz = z + offsets[k].dz;
        const int lx = nx < 0 ? -1 : (nx >= kDim ? 1 : 0);
        const int ly = ny < 0 ? -1 : (ny >= kDim ? 1 : 0);
        const int lz = nz < 0 ? -1 : (nz >= kDim ? 1 : 0);
        const int32_t* values = around[(lx + 1) + 3 * (ly + 1) + 9 * (lz + 1)];
        if (!values) continue;
        const int32_t q = values[((nx - lx * kDim) << 6) | ((ny - ly * kDim) << 3) | (nz - lz * kDim)];
        if (q >= 0) fn(p, q, k);
      }
    }
  }

  template <class Fn>
  void forEach(Fn&& fn) const {
    for (std::size_t i = 0; i < leaves_.size(); ++i) forEachInLeaf(i, fn);
  }

  // Every link, leaves in parallel, in the order forEach() visits them: for passes that look at
  // the links more than once.
  std::vector<Link> all() const {
    constexpr std::size_t kLeavesPerChunk = 64;
    const std::size_t chunks = (leaves_.size() + kLeavesPerChunk - 1) / kLeavesPerChunk;
    std::vector<std::vector<Link>> parts(chunks);
    tbb::parallel_for(std::size_t{0}, chunks, [&](std::size_t c) {
      std::vector<Link>& out = parts[c];
      const std::size_t end = std::min(leaves_.size(), (c + 1) * kLeavesPerChunk);
      for (std::size_t l = c * kLeavesPerChunk; l < end; ++l)
        forEachInLeaf(l, [&](int32_t p, int32_t q, std::size_t k) { out.push_back({p, q, static_cast<uint8_t>(k)}); });
    });
    std::size_t total = 0;
    for (const std::vector<Link>& part : parts) total += part.size();
    std::vector<Link> links;
    links.reserve(total);
    for (const std::vector<Link>& part : parts) links.insert(links.end(), part.begin(), part.end());
    return links;
  }

 private:
  const openvdb::Int32Tree& tree_;
  std::vector<const IndexLeaf*> leaves_;
};

}  // namespace semfuse::objects::detail
