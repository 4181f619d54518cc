#include "semfuse/objects/grouping.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <utility>

#include <tbb/parallel_for.h>

#include "surface_links.hpp"
#include "union_find.hpp"

namespace semfuse::objects {
namespace {

using detail::Link;
using detail::SurfaceLinks;
using detail::UnionFind;

double cosDegrees(double degrees) { return std::cos(degrees * M_PI / 180.0); }

// A step from one surface to a parallel one beside it, along their normals: across a ledge too
// narrow to be resolved (a box standing near the edge of a box), not along one surface. Along a
// surface the step is tangent to both normals, or leaves the surface's layer of voxels by one
// voxel where it crosses from one layer to the next; across a convex or concave edge it leaves one
// side's surface as it enters the other's, so the two normals see it with opposite signs.
// `offset` in voxels.
bool isLedgeStep(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& offset) {
  constexpr float kMinAlongNormals = 1.5f * 1.5f;  // voxels, squared
  return a.dot(offset) * b.dot(offset) > kMinAlongNormals;
}

// A boundary between two regions, seen from one of them.
struct Side {
  uint32_t links = 0;
  uint32_t concave = 0;                              // of the steps between voxels of one label
  Eigen::Vector3f mine = Eigen::Vector3f::Zero();    // sum of this region's normals at the steps
  Eigen::Vector3f theirs = Eigen::Vector3f::Zero();  // and the other region's

  Side& operator+=(const Side& other) {
    links += other.links;
    concave += other.concave;
    mine += other.mine;
    theirs += other.theirs;
    return *this;
  }
  Side flipped() const { return {links, concave, theirs, mine}; }
};

// Panoptic instances of a region's voxels: the one most of them name, if it is most of those that
// name any.
class InstanceVotes {
 public:
  void add(uint32_t instance, uint64_t count = 1) {
    if (instance == 0) return;
    for (auto& [id, n] : votes_)
      if (id == instance) {
        n += count;
        return;
      }
    votes_.emplace_back(instance, count);
  }
  void add(const InstanceVotes& other) {
    for (const auto& [instance, count] : other.votes_) add(instance, count);
  }
  uint32_t dominant() const {
    uint64_t total = 0, best = 0;
    uint32_t winner = 0;
    for (const auto& [instance, count] : votes_) {
      total += count;
      if (count > best) best = count, winner = instance;
    }
    return 2 * best > total ? winner : 0;
  }

 private:
  std::vector<std::pair<uint32_t, uint64_t>> votes_;
};

// A region of the adjacency graph: a patch, or patches merged.
struct Region {
  bool alive = true;
  double area = 0.0;
  std::vector<std::pair<LabelId, double>> label_areas;  // area per label
  LabelId label = kUnlabeled;                           // the label of most of the area
  InstanceVotes instances;
  openvdb::CoordBBox bounds;                     // of its voxels
  std::unordered_map<int32_t, Side> neighbours;  // while merging along boundaries (buildNeighbours)

  void addLabelArea(LabelId id, double a) {
    for (auto& [l, sum] : label_areas)
      if (l == id) {
        sum += a;
        return;
      }
    label_areas.emplace_back(id, a);
  }
  void updateLabel() {
    double best = -1.0;
    for (const auto& [l, sum] : label_areas)
      if (sum > best) best = sum, label = l;
  }
};

class Grouper {
 public:
  Grouper(const SurfaceVoxels& surface, const ObjectParams& params)
      : surface_(surface), params_(params), links_(SurfaceLinks(surface).all()) {}

  Grouping run() {
    findPatches();
    measureBoundaries();
    // Crumbs (the strips along creases and rounded edges, a few voxels wide) join the patch they
    // touch most first: judged on their own, a chain of them would join what their neighbours'
    // boundary separates.
    absorbSmall(crumbArea(), /*same_label_only=*/true);
    buildNeighbours();
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return convexBoundary(a, b, side); });
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return partOf(a, b, side); });
    absorbSmall(params_.min_object_area_m2, /*same_label_only=*/false);
    // Pieces just absorbed may have been all that lay between two objects: their boundary is
    // direct now.
    buildNeighbours();
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return partOf(a, b, side); });
    absorbEnclosed();
    return finish();
  }

 private:
  // The step from p to q = p + linkOffsets()[k] turns concave (or crosses a ledge): the normals
  // turn towards each other along it.
  bool isConcaveStep(const SurfaceVoxel& p, const SurfaceVoxel& q, std::size_t k) const {
    const detail::LinkOffset& offset = detail::linkOffsets()[k];
    return (q.normal - p.normal).dot(offset.direction) < -static_cast<float>(params_.concavity_tolerance) ||
           isLedgeStep(p.normal, q.normal, offset.offset);
  }

  // Two instances are two objects when a segmentation saw them apart.
  bool instancesConflict(uint32_t a, uint32_t b) const {
    return a != 0 && b != 0 && a != b && surface_.instancesSeenApart(a, b);
  }

  // Stage 1: smooth, locally convex patches of one label.
  void findPatches() {
    UnionFind voxels(surface_.size());
    // Each patch's sum of normals: two patches join only while their mean normals agree too, so
    // that a patch cannot drift round a rounded crease a few degrees per voxel.
    std::vector<Eigen::Vector3f> normal_sum(surface_.size());
    for (std::size_t i = 0; i < surface_.size(); ++i) normal_sum[i] = surface_[i].normal;
    // Each patch's instance (the first of its voxels that has one): voxels without instance
    // evidence, along the seam where two touching objects meet, must not chain them together.
    std::vector<uint32_t> patch_instance(surface_.size());
    for (std::size_t i = 0; i < surface_.size(); ++i) patch_instance[i] = surface_[i].instance;
    const float cos_smooth = static_cast<float>(cosDegrees(params_.smooth_angle_deg));
    for (const auto& [p, q, k] : links_) {
      const SurfaceVoxel& a = surface_[p];
      const SurfaceVoxel& b = surface_[q];
      if (a.label != b.label || instancesConflict(a.instance, b.instance)) continue;
      if (a.normal.dot(b.normal) < cos_smooth) continue;
      if (isConcaveStep(a, b, k)) continue;
      const int32_t rp = voxels.find(p), rq = voxels.find(q);
      if (rp == rq) continue;
      const Eigen::Vector3f sum = normal_sum[rp] + normal_sum[rq];
      if (normal_sum[rp].dot(normal_sum[rq]) < cos_smooth * normal_sum[rp].norm() * normal_sum[rq].norm()) continue;
      if (instancesConflict(patch_instance[rp], patch_instance[rq])) continue;
      const uint32_t instance = patch_instance[rp] != 0 ? patch_instance[rp] : patch_instance[rq];
      voxels.unite(rp, rq);
      normal_sum[voxels.find(rp)] = sum;
      patch_instance[voxels.find(rp)] = instance;
    }
    const int32_t count = voxels.compact(patch_of_);
    regions_.assign(count, Region{});
    for (std::size_t i = 0; i < surface_.size(); ++i) {
      Region& region = regions_[patch_of_[i]];
      region.area += surface_[i].area_m2;
      region.addLabelArea(surface_[i].label, surface_[i].area_m2);
      region.instances.add(surface_[i].instance);
      region.bounds.expand(surface_[i].ijk);
    }
    for (Region& region : regions_) region.updateLabel();
    region_of_ = UnionFind(regions_.size());
  }

  // The steps between different patches, of any label, summed per pair of patches: ordered by
  // pair, each pair's steps added in link order. The links between patches are bucketed by lower
  // patch (a counting sort keeps link order), then each bucket is summed per pair in parallel.
  void measureBoundaries() {
    struct Crossing {
      int32_t high;   // the higher patch
      uint32_t link;  // index into links_
    };
    std::vector<std::size_t> bucket(regions_.size() + 1, 0);
    for (const Link& link : links_) {
      const int32_t a = patch_of_[link.p], b = patch_of_[link.q];
      if (a != b) ++bucket[std::min(a, b) + 1];
    }
    for (std::size_t r = 0; r < regions_.size(); ++r) bucket[r + 1] += bucket[r];
    std::vector<Crossing> crossings(bucket.back());
    std::vector<std::size_t> cursor(bucket.begin(), bucket.end() - 1);
    for (uint32_t i = 0; i < links_.size(); ++i) {
      const int32_t a = patch_of_[links_[i].p], b = patch_of_[links_[i].q];
      if (a != b) crossings[cursor[std::min(a, b)]++] = {std::max(a, b), i};
    }
    std::vector<std::vector<Boundary>> of_low(regions_.size());
    tbb::parallel_for(std::size_t{0}, regions_.size(), [&](std::size_t r) {
      const auto begin = crossings.begin() + static_cast<std::ptrdiff_t>(bucket[r]);
      const auto end = crossings.begin() + static_cast<std::ptrdiff_t>(bucket[r + 1]);
      std::stable_sort(begin, end, [](const Crossing& x, const Crossing& y) { return x.high < y.high; });
      std::vector<Boundary>& out = of_low[r];
      for (auto it = begin; it != end; ++it) {
        if (out.empty() || out.back().high != it->high) out.push_back({static_cast<int32_t>(r), it->high, Side{}});
        out.back().side += stepSeenFrom(static_cast<int32_t>(r), links_[it->link]);
      }
    });
    std::size_t total = 0;
    for (const auto& part : of_low) total += part.size();
    boundaries_.clear();
    boundaries_.reserve(total);
    for (const auto& part : of_low) boundaries_.insert(boundaries_.end(), part.begin(), part.end());
  }

  // One link's step between two patches, seen from `patch`, one of them.
  Side stepSeenFrom(int32_t patch, const Link& link) const {
    Side step;
    step.links = 1;
    const SurfaceVoxel& vp = surface_[link.p];
    const SurfaceVoxel& vq = surface_[link.q];
    if (vp.label == vq.label) {
      step.concave = isConcaveStep(vp, vq, link.k);
      step.mine = vp.normal;
      step.theirs = vq.normal;
    }
    return patch_of_[link.p] == patch ? step : step.flipped();
  }

  // The regions' neighbour maps from the patches' boundaries, for merging along boundaries: built
  // when many merges have made the regions few.
  void buildNeighbours() {
    for (Region& region : regions_) region.neighbours.clear();
    for (const Boundary& boundary : boundaries_) {
      const int32_t a = region_of_.find(boundary.low), b = region_of_.find(boundary.high);
      if (a == b) continue;
      regions_[a].neighbours[b] += boundary.side;
      regions_[b].neighbours[a] += boundary.side.flipped();
    }
  }

  // Region b joins region a, `a` staying the root; their neighbour maps are left alone.
  void joinRegions(int32_t a, int32_t b) {
    Region& keep = regions_[a];
    Region& gone = regions_[b];
    region_of_.attach(b, a);
    keep.area += gone.area;
    for (const auto& [label, area] : gone.label_areas) keep.addLabelArea(label, area);
    keep.updateLabel();
    keep.instances.add(gone.instances);
    keep.bounds.expand(gone.bounds);
    gone.alive = false;
  }

  // Merges region b into region a with their neighbour maps; returns the survivor (the one with
  // more neighbours, whose map is kept).
  int32_t merge(int32_t a, int32_t b) {
    if (regions_[a].neighbours.size() < regions_[b].neighbours.size()) std::swap(a, b);
    joinRegions(a, b);
    Region& keep = regions_[a];
    Region& gone = regions_[b];
    keep.neighbours.erase(b);
    for (auto& [n, side] : gone.neighbours) {
      if (n == a) continue;
      keep.neighbours[n] += side;
      auto& theirs = regions_[n].neighbours;
      const auto old = theirs.find(b);
      theirs[a] += old->second;
      theirs.erase(old);
    }
    gone.neighbours.clear();
    return a;
  }

  // Merges neighbouring regions for which `accept(a, b, boundary seen from a)` holds, strongest
  // boundaries (most steps) first, judging each on the boundary as it stands when its turn comes:
  // a piece between two regions that joins one of them is judged together with it.
  template <class Accept>
  void mergeWhile(Accept&& accept) {
    using Entry = std::tuple<uint32_t, int32_t, int32_t>;  // (links, a, b)
    std::priority_queue<Entry> queue;
    for (int32_t a = 0; a < static_cast<int32_t>(regions_.size()); ++a)
      if (regions_[a].alive)
        for (const auto& [b, side] : regions_[a].neighbours)
          if (a < b && regions_[a].label == regions_[b].label) queue.emplace(side.links, a, b);
    while (!queue.empty()) {
      const auto [links, a, b] = queue.top();
      queue.pop();
      if (!regions_[a].alive || !regions_[b].alive) continue;
      const auto found = regions_[a].neighbours.find(b);
      if (found == regions_[a].neighbours.end() || found->second.links != links) continue;  // changed since
      if (regions_[a].label != regions_[b].label || !accept(a, b, found->second)) continue;
      const std::vector<int32_t> changed =
          neighboursOf(regions_[a].neighbours.size() < regions_[b].neighbours.size() ? a : b);
      const int32_t survivor = merge(a, b);
      for (int32_t n : changed) {
        if (n == a || n == b || !regions_[n].alive) continue;
        const auto side = regions_[survivor].neighbours.find(n);
        if (side != regions_[survivor].neighbours.end() && regions_[n].label == regions_[survivor].label)
          queue.emplace(side->second.links, survivor, n);
      }
    }
  }

  std::vector<int32_t> neighboursOf(int32_t region) const {
    std::vector<int32_t> out;
    out.reserve(regions_[region].neighbours.size());
    for (const auto& [n, side] : regions_[region].neighbours) out.push_back(n);
    return out;
  }

  // Stage 2: most steps across the boundary are convex or flat.
  bool convexBoundary(int32_t a, int32_t b, const Side& side) const {
    if (instancesConflict(regions_[a].instances.dominant(), regions_[b].instances.dominant())) return false;
    return side.concave <= params_.concave_boundary_share * side.links;
  }

  // Stage 3, between objects only: a chain of small pieces along a crease, each judged on a few
  // blended normals, would otherwise join what the crease as a whole separates.
  bool partOf(int32_t a, int32_t b, const Side& side) const {
    if (regions_[a].area < params_.min_object_area_m2 || regions_[b].area < params_.min_object_area_m2) return false;
    const uint32_t ia = regions_[a].instances.dominant(), ib = regions_[b].instances.dominant();
    if (instancesConflict(ia, ib)) return false;
    if (ia != 0 && ia == ib) return true;
    return !(upKnown() && opensUpwards(side));
  }

  bool upKnown() const { return params_.up.norm() > 0.5; }

  // The crease's valley opens along the sum of the two sides' mean normals: upwards where one
  // side stands on the other's top face, downwards under a table top, sideways between two walls.
  bool opensUpwards(const Side& side) const {
    if (side.mine.norm() == 0.0f || side.theirs.norm() == 0.0f) return false;
    const Eigen::Vector3f valley = side.mine.normalized() + side.theirs.normalized();
    const float cos_valley = static_cast<float>(cosDegrees(params_.support_valley_angle_deg));
    return valley.norm() > 0.0f && valley.normalized().dot(params_.up.normalized().cast<float>()) >= cos_valley;
  }

  // A patch smaller than this is a crumb: about ten voxel faces.
  double crumbArea() const { return 10.0 * surface_.voxelSize() * surface_.voxelSize(); }

  // Regions smaller than `threshold` join the larger neighbour they have most steps to (the
  // first in boundaries_ on a tie), of their own label first (or only), in rounds: a piece that touched
  // only small ones may touch a large one after a round. Stage 4 with the minimum object area;
  // before stage 2 with crumbArea(). Works on the patches' boundaries, not the neighbour maps:
  // most patches are crumbs, and joining them one by one in the maps costs more than the rest.
  void absorbSmall(double threshold, bool same_label_only) {
    struct Candidate {
      int32_t small, large;
      uint32_t links;
      uint32_t first;  // index of the pair's first boundary
    };
    // A large region stays large: the boundaries between two large ones are dropped for good.
    std::vector<uint32_t> touching_small(boundaries_.size());
    std::iota(touching_small.begin(), touching_small.end(), 0u);
    std::vector<Candidate> candidates;
    for (int round = 0; round < 8; ++round) {
      candidates.clear();
      std::size_t kept = 0;
      for (const uint32_t i : touching_small) {
        const Boundary& boundary = boundaries_[i];
        const int32_t a = region_of_.find(boundary.low), b = region_of_.find(boundary.high);
        if (a == b) continue;
        const bool small_a = regions_[a].area < threshold, small_b = regions_[b].area < threshold;
        if (!small_a && !small_b) continue;
        touching_small[kept++] = i;
        if (small_a && !small_b) candidates.push_back({a, b, boundary.side.links, i});
        if (small_b && !small_a) candidates.push_back({b, a, boundary.side.links, i});
      }
      touching_small.resize(kept);
      std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
        return std::tie(x.small, x.large, x.first) < std::tie(y.small, y.large, y.first);
      });
      // Summed per pair of regions (a pair's boundaries are consecutive, its first one first).
      std::vector<Candidate> pairs;
      for (const Candidate& c : candidates) {
        if (!pairs.empty() && pairs.back().small == c.small && pairs.back().large == c.large)
          pairs.back().links += c.links;
        else pairs.push_back(c);
      }
      // Per small region (its pairs are consecutive), the large one to join.
      auto better = [](const Candidate& c, const Candidate* best) {
        return !best || c.links > best->links || (c.links == best->links && c.first < best->first);
      };
      std::vector<std::pair<int32_t, int32_t>> moves;  // (small, into)
      for (std::size_t begin = 0, end = 0; begin < pairs.size(); begin = end) {
        const int32_t small = pairs[begin].small;
        const Candidate* same = nullptr;
        const Candidate* any = nullptr;
        for (end = begin; end < pairs.size() && pairs[end].small == small; ++end) {
          if (regions_[pairs[end].large].label == regions_[small].label && better(pairs[end], same)) same = &pairs[end];
          if (better(pairs[end], any)) any = &pairs[end];
        }
        const Candidate* into = same ? same : (same_label_only ? nullptr : any);
        if (into) moves.emplace_back(small, into->large);
      }
      if (moves.empty()) break;
      // A small region joins a large one, which no move of this round joins elsewhere.
      for (const auto& [small, into] : moves) joinRegions(into, small);
    }
  }

  // Stage 5: a piece of a large object that what stands in front of it cut off (a strip of floor
  // between two chairs, the edge of a cabinet behind a sphere) shares no link with it, but lies
  // within its box and is much smaller: it joins the largest such object of its label.
  void absorbEnclosed() {
    const int margin = std::max(1, static_cast<int>(std::lround(params_.enclosing_margin_m / surface_.voxelSize())));
    std::vector<int32_t> alive;
    for (int32_t r = 0; r < static_cast<int32_t>(regions_.size()); ++r)
      if (regions_[r].alive) alive.push_back(r);
    std::sort(alive.begin(), alive.end(), [&](int32_t a, int32_t b) { return regions_[a].area > regions_[b].area; });
    // Earlier merges kept whichever index had more neighbours: regions are looked up through region_of_.
    for (std::size_t i = alive.size(); i-- > 0;) {
      const int32_t small = region_of_.find(alive[i]);
      const Region& piece = regions_[small];
      for (std::size_t j = 0; j < i; ++j) {
        const int32_t large = region_of_.find(alive[j]);
        const Region& whole = regions_[large];
        if (large == small || whole.label != piece.label) continue;
        if (whole.area < params_.enclosed_area_ratio * piece.area) continue;
        if (instancesConflict(whole.instances.dominant(), piece.instances.dominant())) continue;
        openvdb::CoordBBox grown = whole.bounds;
        grown.expand(margin);
        if (!grown.isInside(piece.bounds)) continue;
        joinRegions(large, small);
        break;
      }
    }
  }

  Grouping finish() {
    std::vector<int32_t> roots;
    for (int32_t r = 0; r < static_cast<int32_t>(regions_.size()); ++r)
      if (regions_[r].alive) roots.push_back(r);
    auto is_object = [&](int32_t r) { return regions_[r].area >= params_.min_object_area_m2; };
    std::stable_sort(roots.begin(), roots.end(), [&](int32_t a, int32_t b) {
      if (is_object(a) != is_object(b)) return is_object(a);
      return regions_[a].area > regions_[b].area;
    });
    Grouping out;
    std::vector<int32_t> index_of_root(regions_.size(), -1);
    for (int32_t root : roots) {
      index_of_root[root] = static_cast<int32_t>(out.groups.size());
      Group group;
      group.label = regions_[root].label;
      group.area_m2 = regions_[root].area;
      group.fragment = !is_object(root);
      group.instance = regions_[root].instances.dominant();
      out.groups.push_back(group);
    }
    out.group_of.resize(surface_.size());
    for (std::size_t i = 0; i < surface_.size(); ++i) {
      const int32_t g = index_of_root[region_of_.find(patch_of_[i])];
      out.group_of[i] = g;
      ++out.groups[g].voxel_count;
    }
    return out;
  }

  const SurfaceVoxels& surface_;
  const ObjectParams& params_;
  std::vector<Link> links_;  // visited twice: found once
  struct Boundary {
    int32_t low, high;  // patches, low < high
    Side side;          // seen from `low`
  };
  std::vector<int32_t> patch_of_;     // per surface voxel
  std::vector<Boundary> boundaries_;  // between patches, by pair
  std::vector<Region> regions_;       // per patch; merged ones are not alive
  UnionFind region_of_{0};            // patch -> the region it is part of
};

}  // namespace

Grouping groupSurface(const SurfaceVoxels& surface, const ObjectParams& params) {
  return Grouper(surface, params).run();
}

}  // namespace semfuse::objects
