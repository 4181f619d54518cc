#include "waves.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace semfuse::esdf::detail {
namespace {

struct Step {
  int x, y, z;
};
constexpr std::array<Step, 6> kFaces = {{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};
// The lower wave hands sites on to all 26 neighbours: over faces alone, sites reach diagonal
// voxels by staircase paths whose last step can pick a site a voxel farther than the nearest.
const std::array<Step, 26> kAllNeighbours = [] {
  std::array<Step, 26> all{};
  int i = 0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) all[i++] = {x, y, z};
  return all;
}();

// The queue is bucketed by a quarter voxel of distance (voxblox buckets too), so most voxels
// settle on their first visit instead of being improved again by a later, nearer wave, and
// sites reach voxels in nearly the order an exact Dijkstra would (whole-voxel buckets left some a
// fifth of a voxel farther from their best site).
constexpr float kBucketsPerVoxel = 4.0f;

// A voxel's place in its bucket as one integer: its leaf's origin (in leaves, 18 bits per axis,
// offset to be non-negative) and its offset in the leaf. Sorting these integers costs a fraction
// of comparing origins read through the leaves' pointers, which miss the cache. Leaves 2^18 apart
// (2.6 km of 1 cm voxels) would share a key: their order is then the sort's, not the origins'.
uint64_t queueOrder(const VoxelRef& voxel) {
  constexpr int kBits = 18;
  constexpr int kOffsetBits = 3 * FieldLeaf::LOG2DIM;  // voxel.n
  constexpr int64_t kBias = int64_t{1} << (kBits - 1);
  constexpr uint64_t kMask = (uint64_t{1} << kBits) - 1;
  const openvdb::Coord& origin = voxel.leaf->origin();
  const auto axis = [&](int v) { return static_cast<uint64_t>((v >> FieldLeaf::LOG2DIM) + kBias) & kMask; };
  return (axis(origin.x()) << (kOffsetBits + 2 * kBits)) | (axis(origin.y()) << (kOffsetBits + kBits)) |
         (axis(origin.z()) << kOffsetBits) | voxel.n;
}

// Whether a voxel on the `inside` side of the surface can take a site from (or give one to) a
// voxel whose state is (known, v): unknown voxels are ways through for the free side only.
bool sameSide(bool known, const EsdfVoxel& v, bool inside) { return known ? v.inside == inside : !inside; }

}  // namespace

Waves::Waves(FieldTree& tree, float max_voxels) : max_voxels_(max_voxels), neighbourhood_(tree), sites_(tree) {}

void Waves::run(UpdateStats& stats) {
  // Leaves may have come and gone since the last update: nothing cached survives it.
  neighbourhood_.reset();
  sites_.clear();
  raise(stats);
  seedOrphans();
  lower(stats);
}

// Clears every voxel whose site is one of the raise seeds, following the 6-neighbour chains the
// lower wave grew them along; the cleared voxels become orphans.
void Waves::raise(UpdateStats& stats) {
  for (std::size_t head = 0; head < raise_.size(); ++head) {
    const RaiseItem item = raise_[head];
    for (const Step& s : kFaces) {
      VoxelRef w;
      if (!neighbourhood_.step(item.from, s.x, s.y, s.z, w)) continue;
      EsdfVoxel v = w.voxel();
      if (!v.has_site || v.is_site || v.site(w.coord()) != item.site) continue;
      v.has_site = false;
      v.dx = v.dy = v.dz = 0;
      v.site_distance = 0;
      w.write(v);
      raise_.push_back({w, item.site});
      orphans_.push_back(w);
      ++stats.cleared;
    }
  }
  raise_.clear();
}

// Every orphan (a voxel without a site) is offered the sites of its 26 neighbours on its side:
// those neighbours join the lower wave. All 26, not the 6 over faces: a region of orphans may
// touch the voxels with sites only at an edge or a corner (thin regions inside objects do), and
// would then be left without a distance.
void Waves::seedOrphans() {
  // Neighbouring orphans share neighbours: each voxel is queued once however many orphans border
  // it (a new leaf's 512 orphans would queue their neighbours up to six times). The voxel itself
  // carries the mark while the orphans are seeded.
  for (const VoxelRef& orphan : orphans_) {
    const EsdfVoxel o = orphan.voxel();
    if (o.has_site) continue;
    const bool inside = orphan.known() && o.inside;
    for (const Step& s : kAllNeighbours) {
      VoxelRef n;
      if (!neighbourhood_.step(orphan, s.x, s.y, s.z, n)) continue;
      const PackedEsdf packed = n.packed();
      if (isMarked(packed)) continue;
      const EsdfVoxel v = unpackEsdf(packed);
      if (!v.has_site || !sameSide(n.known(), v, inside)) continue;
      n.leaf->setValueOnly(n.n, withMark(packed));
      marked_.push_back(n);
      push(n, v.magnitude());
    }
  }
  for (const VoxelRef& voxel : marked_) voxel.leaf->setValueOnly(voxel.n, withoutMark(voxel.packed()));
  marked_.clear();
  orphans_.clear();
}

// From the queued voxels outwards, nearest first: a neighbour on the same side takes the voxel's
// site when that site is nearer than its own (or it has none) and within the maximum distance.
void Waves::lower(UpdateStats& stats) {
  for (const VoxelRef& seed : seeds_) {
    const EsdfVoxel v = seed.voxel();
    if (v.has_site) push(seed, v.magnitude());
  }
  seeds_.clear();
  for (current_ = 0; current_ < buckets_.size(); ++current_) {
    // Any order within a bucket will do: leaf by leaf, the neighbours of one voxel are still in
    // the cache for the next (in queue order the field is read all over the map). Leaves go by
    // origin, not address, so that the same changes give the same field in every run (which of
    // two nearly equal sites a voxel keeps depends on the order).
    std::sort(buckets_[current_].begin(), buckets_[current_].end(),
              [](const Queued& a, const Queued& b) { return a.order < b.order; });
    // Relaxing a voxel queues its neighbours in this bucket or later ones, never earlier (and
    // may grow the queue: no references into it across a relax).
    for (std::size_t head = 0; head < buckets_[current_].size(); ++head) relax(buckets_[current_][head], stats);
    buckets_[current_].clear();
  }
  current_ = 0;
}

void Waves::push(const VoxelRef& voxel, float distance) {
  // Never behind the bucket in hand (a re-seeded neighbour can be nearer than it): it would be
  // left unvisited.
  const auto bucket = std::max(current_, static_cast<std::size_t>(std::max(0.0f, distance) * kBucketsPerVoxel));
  if (bucket >= buckets_.size()) buckets_.resize(bucket + 1);
  buckets_[bucket].push_back({voxel, distance, queueOrder(voxel)});
}

void Waves::relax(Queued item, UpdateStats& stats) {
  ++stats.popped;
  const VoxelRef u = item.voxel;
  EsdfVoxel from = u.voxel();
  if (!from.has_site) return;
  // A nearer site reached it after it was queued: the later entry hands that one on.
  if (from.magnitude() < item.distance - 1e-4f) return;
  const bool inside = u.known() && from.inside;
  if (!from.is_site) {
    // The site may have gone since this voxel took it (a chain the raise wave could not follow).
    PackedEsdf packed;
    const bool site_known = sites_.probeValue(from.site(u.coord()), packed);
    const EsdfVoxel s = unpackEsdf(packed);
    if (!site_known || !s.is_site || s.inside != inside) {
      from.has_site = false;
      from.dx = from.dy = from.dz = 0;
      u.write(from);
      pushNeighboursWithSites(u, inside);
      return;
    }
    if (s.site_distance != from.site_distance) {
      from.site_distance = s.site_distance;
      u.write(from);
    }
  }
  const float site_distance = from.site_distance * (1.0f / 255.0f);
  for (const Step& s : kAllNeighbours) {
    VoxelRef w_ref;
    if (!neighbourhood_.step(u, s.x, s.y, s.z, w_ref)) continue;
    EsdfVoxel w = w_ref.voxel();
    if (w.is_site || !sameSide(w_ref.known(), w, inside)) continue;
    // The site seen from the neighbour: from's offset less the step.
    const int ox = from.dx - s.x, oy = from.dy - s.y, oz = from.dz - s.z;
    const float candidate = std::sqrt(static_cast<float>(ox * ox + oy * oy + oz * oz)) + site_distance;
    if (candidate > max_voxels_) continue;
    if (w.has_site && candidate >= w.magnitude() - 1e-3f) continue;
    w.dx = static_cast<int16_t>(ox);
    w.dy = static_cast<int16_t>(oy);
    w.dz = static_cast<int16_t>(oz);
    w.site_distance = from.site_distance;
    w.has_site = true;
    w.inside = inside;
    w_ref.write(w);
    push(w_ref, candidate);
    ++stats.relaxed;
  }
}

void Waves::pushNeighboursWithSites(const VoxelRef& voxel, bool inside) {
  for (const Step& s : kFaces) {
    VoxelRef n;
    if (!neighbourhood_.step(voxel, s.x, s.y, s.z, n)) continue;
    const EsdfVoxel v = n.voxel();
    if (v.has_site && sameSide(n.known(), v, inside)) push(n, v.magnitude());
  }
}

}  // namespace semfuse::esdf::detail
