#include "semfuse/objects/grouping.hpp"

#include <algorithm>
#include <cmath>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "surface_links.hpp"
#include "union_find.hpp"

namespace semfuse::objects {
namespace {

using detail::Link;
using detail::SurfaceLinks;
using detail::UnionFind;

double cosDegrees(double degrees) { return std::cos(degrees * M_PI / 180.0); }

bool instancesConflict(uint32_t a, uint32_t b) { return a != 0 && b != 0 && a != b; }

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
  openvdb::CoordBBox bounds;  // of its voxels
  std::unordered_map<int32_t, Side> neighbours;

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
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return convexBoundary(a, b, side); });
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return partOf(a, b, side); });
    absorbSmall(params_.min_object_area_m2, /*same_label_only=*/false);
    // Pieces just absorbed may have been all that lay between two objects: their boundary is
    // direct now.
    mergeWhile([&](int32_t a, int32_t b, const Side& side) { return partOf(a, b, side); });
    absorbEnclosed();
    return finish();
  }

 private:
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
    const float tolerance = static_cast<float>(params_.concavity_tolerance);
    const auto& offsets = detail::linkOffsets();
    for (const auto& [p, q, k] : links_) {
      const SurfaceVoxel& a = surface_[p];
      const SurfaceVoxel& b = surface_[q];
      if (a.label != b.label || instancesConflict(a.instance, b.instance)) continue;
      if (a.normal.dot(b.normal) < cos_smooth) continue;
      const Eigen::Vector3f& d = offsets[k].direction;
      if ((b.normal - a.normal).dot(d) < -tolerance || isLedgeStep(a.normal, b.normal, offsets[k].offset)) continue;
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

  // The steps between different patches, of any label: summed per pair of patches in link order,
  // then entered in the patches' neighbour maps in the order the pairs first occur (the maps'
  // iteration order breaks ties later), as adding each step to the maps directly would.
  void measureBoundaries() {
    const float tolerance = static_cast<float>(params_.concavity_tolerance);
    const auto& offsets = detail::linkOffsets();
    struct Boundary {
      int32_t low, high;  // patches, low < high
      Side side;          // seen from `low`
    };
    std::vector<Boundary> boundaries;  // in order of first occurrence
    // Per patch, the boundaries it is the lower patch of: (other patch, index into boundaries).
    // Patches have a handful of neighbours: a linear search beats hashing.
    std::vector<std::vector<std::pair<int32_t, int32_t>>> boundaries_of(regions_.size());
    for (const auto& [p, q, k] : links_) {
      const int32_t a = patch_of_[p], b = patch_of_[q];
      if (a == b) continue;
      Side step;
      step.links = 1;
      const SurfaceVoxel& vp = surface_[p];
      const SurfaceVoxel& vq = surface_[q];
      if (vp.label == vq.label) {
        const Eigen::Vector3f& d = offsets[k].direction;
        step.concave =
            (vq.normal - vp.normal).dot(d) < -tolerance || isLedgeStep(vp.normal, vq.normal, offsets[k].offset);
        step.mine = vp.normal;
        step.theirs = vq.normal;
      }
      const int32_t low = std::min(a, b), high = std::max(a, b);
      if (a != low) step = step.flipped();
      auto& known = boundaries_of[low];
      const auto found = std::find_if(known.begin(), known.end(), [&](const auto& b) { return b.first == high; });
      if (found != known.end()) {
        boundaries[found->second].side += step;
      } else {
        known.emplace_back(high, static_cast<int32_t>(boundaries.size()));
        boundaries.push_back({low, high, Side{} += step});
      }
    }
    for (const Boundary& boundary : boundaries) {
      regions_[boundary.low].neighbours.emplace(boundary.high, boundary.side);
      regions_[boundary.high].neighbours.emplace(boundary.low, boundary.side.flipped());
    }
  }

  // Merges region b into region a; returns the survivor (the one with more neighbours, whose
  // map is kept).
  int32_t merge(int32_t a, int32_t b) {
    if (regions_[a].neighbours.size() < regions_[b].neighbours.size()) std::swap(a, b);
    Region& keep = regions_[a];
    Region& gone = regions_[b];
    region_of_.attach(b, a);
    keep.area += gone.area;
    for (const auto& [label, area] : gone.label_areas) keep.addLabelArea(label, area);
    keep.updateLabel();
    keep.instances.add(gone.instances);
    keep.bounds.expand(gone.bounds);
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
    gone.alive = false;
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

  // Regions smaller than `threshold` join the larger neighbour they have most steps to, of their
  // own label first (or only), in rounds: a piece that touched only small ones may touch a large
  // one after a round. Stage 4 with the minimum object area; before stage 2 with crumbArea().
  void absorbSmall(double threshold, bool same_label_only) {
    for (int round = 0; round < 8; ++round) {
      std::vector<std::pair<int32_t, int32_t>> moves;  // (small, into)
      for (int32_t r = 0; r < static_cast<int32_t>(regions_.size()); ++r) {
        const Region& region = regions_[r];
        if (!region.alive || region.area >= threshold) continue;
        int32_t same = -1, any = -1;
        uint32_t same_links = 0, any_links = 0;
        for (const auto& [n, side] : region.neighbours) {
          if (regions_[n].area < threshold) continue;
          if (regions_[n].label == region.label && side.links > same_links) same = n, same_links = side.links;
          if (side.links > any_links) any = n, any_links = side.links;
        }
        const int32_t into = same >= 0 ? same : (same_label_only ? -1 : any);
        if (into >= 0) moves.emplace_back(r, into);
      }
      if (moves.empty()) break;
      for (const auto& [small, into] : moves) {
        const int32_t a = region_of_.find(small), b = region_of_.find(into);
        if (a != b) merge(a, b);
      }
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
    // A merge keeps whichever index has more neighbours: regions are looked up through region_of_.
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
        merge(large, small);
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
  std::vector<Link> links_;        // visited twice: found once
  std::vector<int32_t> patch_of_;  // per surface voxel
  std::vector<Region> regions_;    // per patch; merged ones are not alive
  UnionFind region_of_{0};         // patch -> the region it is part of
};

}  // namespace

Grouping groupSurface(const SurfaceVoxels& surface, const ObjectParams& params) {
  return Grouper(surface, params).run();
}

}  // namespace semfuse::objects
