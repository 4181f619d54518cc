#include "semfuse/esdf/esdf_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "semfuse/volume/voxel.hpp"

namespace semfuse::esdf {
namespace {

constexpr int kLeafDim = volume::LabeledVolume::kLeafDim;
constexpr int kLeafVoxels = volume::LabeledVolume::kLeafVoxels;
const openvdb::Coord kNeighbours[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
// The lower wave hands sites on to all 26 neighbours: over faces alone, sites reach diagonal
// voxels by staircase paths whose last step can pick a site a voxel farther than the nearest.
const std::array<openvdb::Coord, 26> kAllNeighbours = [] {
  std::array<openvdb::Coord, 26> all{};
  int i = 0;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if (x || y || z) all[i++] = openvdb::Coord(x, y, z);
  return all;
}();

// A site whose distance to the surface changed by less than this (1/255 voxel units, about 0.1
// voxel) keeps the voxels that point at it as they are: their copies of its distance are then off
// by at most that much until a wave passes them. A larger change re-propagates.
constexpr int kSiteDistanceTolerance = 26;

// OpenVDB's leaf offset n = x * 64 + y * 8 + z (local coordinates).
openvdb::Coord localCoord(int n) { return {n >> 6, (n >> 3) & 7, n & 7}; }
int leafOffset(int x, int y, int z) { return (x << 6) | (y << 3) | z; }

struct Classified {
  bool known = false;
  bool inside = false;
  bool site = false;
  uint8_t site_distance = 0;  // 1/255 voxel
};

// What a changed leaf's voxels are now. A site is an observed voxel with a 6-neighbour observed on
// the other side of the surface: a zero crossing lies on the edge between them, wherever the
// projective TSDF's magnitudes put it (at grazing views |tsdf| is several times the true distance,
// but the crossing stays where the surface is). The site's own distance is the nearest crossing
// along its edges, linearly interpolated: |t| / (|t| + |t_neighbour|) of a voxel.
class Classifier {
 public:
  Classifier(double voxel_size, const EsdfParams& params)
      : voxel_(static_cast<float>(voxel_size)), min_weight_(params.min_site_weight) {}

  Classified operator()(const ChangedLeaf& leaf, int n) const {
    Classified c;
    if (leaf.has_geometry && leaf.observed[n]) {
      const volume::PackedVoxel v = leaf.voxels[n];
      const float tsdf = volume::unpackTsdf(v);
      c.known = true;
      c.inside = tsdf < 0.0f;
      if (volume::unpackWeight(v) >= min_weight_) {
        const Crossing crossing = nearestCrossing(leaf, n, tsdf);
        c.site = crossing.axis >= 0;
        c.site_distance = static_cast<uint8_t>(std::lround(crossing.fraction * 255.0f));
      }
    } else if (leaf.observed_free[n]) {
      c.known = true;
    }
    return c;
  }

  // Labeled surface points: for every free-side site with a label, the zero crossing on its
  // nearest crossing edge.
  std::vector<SurfacePoint> surfacePoints(const ChangedLeaf& leaf) const {
    std::vector<SurfacePoint> points;
    if (!leaf.has_geometry) return points;
    for (int n = 0; n < kLeafVoxels; ++n) {
      if (!leaf.observed[n]) continue;
      const volume::PackedVoxel v = leaf.voxels[n];
      const LabelId label = volume::unpackLabel(v);
      const float tsdf = volume::unpackTsdf(v);
      if (label == kUnlabeled || tsdf < 0.0f || volume::unpackWeight(v) < min_weight_) continue;
      const Crossing crossing = nearestCrossing(leaf, n, tsdf);
      if (crossing.axis < 0) continue;
      const openvdb::Coord ijk = leaf.origin + localCoord(n);
      Eigen::Vector3f position(ijk.x() * voxel_, ijk.y() * voxel_, ijk.z() * voxel_);
      position[crossing.axis] += static_cast<float>(crossing.direction) * crossing.fraction * voxel_;
      points.push_back({position, label});
    }
    return points;
  }

 private:
  struct Crossing {
    int axis = -1;  // -1: no neighbour across the surface
    int direction = 0;
    float fraction = 1.0f;
  };

  // The TSDF of the neighbour one step along `axis` in `direction`; false where unobserved.
  static bool neighbourTsdf(const ChangedLeaf& leaf, const openvdb::Coord& local, int axis, int direction, float& out) {
    openvdb::Coord at = local;
    at[axis] += direction;
    if (at[axis] >= 0 && at[axis] < kLeafDim) {
      const int n = leafOffset(at.x(), at.y(), at.z());
      if (!leaf.observed[n]) return false;
      out = volume::unpackTsdf(leaf.voxels[n]);
      return true;
    }
    const int u = axis == 0 ? 1 : 0, v = axis == 2 ? 1 : 2;
    out = leaf.halo[ChangedLeaf::haloIndex(axis, direction > 0, local[u], local[v])];
    return !std::isnan(out);
  }

  static Crossing nearestCrossing(const ChangedLeaf& leaf, int n, float tsdf) {
    Crossing best;
    const openvdb::Coord local = localCoord(n);
    const bool negative = tsdf < 0.0f;
    for (int axis = 0; axis < 3; ++axis)
      for (int direction : {-1, 1}) {
        float other;
        if (!neighbourTsdf(leaf, local, axis, direction, other) || (other < 0.0f) == negative) continue;
        const float fraction = std::abs(tsdf) / (std::abs(tsdf) + std::abs(other));
        if (best.axis < 0 || fraction < best.fraction) best = {axis, direction, fraction};
      }
    return best;
  }

  float voxel_, min_weight_;
};

// The raise and lower waves over the field, on one accessor. Waves on the free side also cross
// the unknown voxels of the field's leaves (inactive, but holding a site like any other voxel):
// a distance is the straight-line distance to the nearest observed surface, and a pocket nobody
// looked into must not make the wave go round it. Queries never read those voxels.
class Waves {
 public:
  static constexpr float kBucketsPerVoxel = 4.0f;

  using Leaf = EsdfGrid::TreeType::LeafNodeType;

  Waves(EsdfGrid& grid, float max_voxels, UpdateStats& stats)
      : values_(grid.tree()), sites_(grid.tree()), max_voxels_(max_voxels), stats_(stats) {}

  Leaf* probeLeaf(const openvdb::Coord& origin) { return values_.probeLeaf(origin); }
  Leaf* touchLeaf(const openvdb::Coord& origin) { return values_.touchLeaf(origin); }

  // False outside the field's leaves. Unknown voxels of a leaf read as free-side voxels.
  bool read(const openvdb::Coord& ijk, EsdfVoxel& voxel, bool& known) {
    const Leaf* leaf = values_.probeConstLeaf(ijk);
    if (!leaf) return false;
    const openvdb::Index n = Leaf::coordToOffset(ijk);
    voxel = unpackEsdf(leaf->getValue(n));
    known = leaf->isValueOn(n);
    return true;
  }
  // Keeps the voxel's known / unknown state.
  void write(const openvdb::Coord& ijk, const EsdfVoxel& voxel) { values_.setValueOnly(ijk, packEsdf(voxel)); }

  void addLower(const openvdb::Coord& ijk) { seeds_.push_back(ijk); }
  void addRaise(const openvdb::Coord& site) { raise_.push_back({site, site}); }
  void addOrphan(const openvdb::Coord& ijk) { orphans_.push_back(ijk); }

  // Clears every voxel whose site is one of the raise seeds, following the 6-neighbour chains the
  // lower wave grew them along; the cleared voxels become orphans.
  void raise() {
    for (std::size_t head = 0; head < raise_.size(); ++head) {
      const auto [from, site] = raise_[head];
      for (const openvdb::Coord& step : kNeighbours) {
        const openvdb::Coord ijk = from + step;
        EsdfVoxel w;
        bool known;
        if (!read(ijk, w, known) || !w.has_site || w.is_site || w.site(ijk) != site) continue;
        w.has_site = false;
        w.dx = w.dy = w.dz = 0;
        w.site_distance = 0;
        write(ijk, w);
        raise_.push_back({ijk, site});
        orphans_.push_back(ijk);
        ++stats_.cleared;
      }
    }
    raise_.clear();
  }

  // Every orphan (a voxel without a site) is offered the sites of its neighbours on its side:
  // those neighbours join the lower wave.
  void seedOrphans() {
    // Neighbouring orphans share neighbours: each voxel is queued once however many orphans
    // border it (a new leaf's 512 orphans would queue their neighbours up to six times).
    openvdb::MaskTree queued;
    openvdb::tree::ValueAccessor<openvdb::MaskTree> marks(queued);
    for (const openvdb::Coord& ijk : orphans_) {
      EsdfVoxel o;
      bool known;
      if (!read(ijk, o, known) || o.has_site) continue;
      const bool inside = known && o.inside;
      for (const openvdb::Coord& step : kNeighbours) {
        const openvdb::Coord n_ijk = ijk + step;
        EsdfVoxel n;
        bool n_known;
        if (!read(n_ijk, n, n_known) || !n.has_site || (n_known ? n.inside != inside : inside)) continue;
        if (marks.isValueOn(n_ijk)) continue;
        marks.setValueOn(n_ijk);
        push(n_ijk, n.magnitude());
      }
    }
    orphans_.clear();
  }

  // From the queued voxels outwards, nearest first: a neighbour on the same side takes the
  // voxel's site when that site is nearer than its own (or it has none) and within the maximum
  // distance. The queue is bucketed by a quarter voxel of distance (voxblox buckets too), so most
  // voxels settle on their first visit instead of being improved again by a later, nearer wave,
  // and sites reach voxels in nearly the order an exact Dijkstra would (whole-voxel buckets left
  // some a fifth of a voxel farther from their best site).
  void lower() {
    for (const openvdb::Coord& ijk : seeds_) {
      EsdfVoxel v;
      bool known;
      if (read(ijk, v, known) && v.has_site) push(ijk, v.magnitude());
    }
    seeds_.clear();
    for (current_ = 0; current_ < buckets_.size(); ++current_) {
      // Relaxing a voxel queues its neighbours in this bucket or later ones, never earlier.
      for (std::size_t head = 0; head < buckets_[current_].size(); ++head) relax(buckets_[current_][head]);
      buckets_[current_].clear();
    }
    current_ = 0;
  }

 private:
  void push(const openvdb::Coord& ijk, float distance) {
    // Never behind the bucket in hand (a re-seeded neighbour can be nearer than it): it would be
    // left unvisited.
    const auto bucket = std::max(current_, static_cast<std::size_t>(std::max(0.0f, distance) * kBucketsPerVoxel));
    if (bucket >= buckets_.size()) buckets_.resize(bucket + 1);
    buckets_[bucket].push_back(ijk);
  }

  void relax(const openvdb::Coord& u) {
    ++stats_.popped;
    EsdfVoxel from;
    bool from_known;
    if (!read(u, from, from_known) || !from.has_site) return;
    const bool inside = from_known && from.inside;
    const openvdb::Coord site = from.site(u);
    if (!from.is_site) {
      // The site may have gone since this voxel took it (a chain the raise wave could not follow).
      // Read through an accessor of its own: the site is often leaves away, and reading it through
      // the neighbourhood's accessor would evict the leaf its 26 neighbours are read from.
      PackedEsdf packed;
      const bool site_known = sites_.probeValue(site, packed);
      const EsdfVoxel s = unpackEsdf(packed);
      if (!site_known || !s.is_site || s.inside != inside) {
        from.has_site = false;
        from.dx = from.dy = from.dz = 0;
        write(u, from);
        pushNeighboursWithSites(u, inside);
        return;
      }
      if (s.site_distance != from.site_distance) {
        from.site_distance = s.site_distance;
        write(u, from);
      }
    }
    const uint8_t site_distance = from.site_distance;
    for (const openvdb::Coord& step : kAllNeighbours) {
      const openvdb::Coord w_ijk = u + step;
      EsdfVoxel w;
      bool known;
      if (!read(w_ijk, w, known) || w.is_site || (known ? w.inside != inside : inside)) continue;
      const openvdb::Coord offset = site - w_ijk;
      const float squared =
          float(offset.x()) * offset.x() + float(offset.y()) * offset.y() + float(offset.z()) * offset.z();
      const float candidate = std::sqrt(squared) + site_distance * (1.0f / 255.0f);
      if (candidate > max_voxels_) continue;
      if (w.has_site && candidate >= w.magnitude() - 1e-3f) continue;
      w.dx = static_cast<int16_t>(offset.x());
      w.dy = static_cast<int16_t>(offset.y());
      w.dz = static_cast<int16_t>(offset.z());
      w.site_distance = site_distance;
      w.has_site = true;
      w.inside = inside;
      write(w_ijk, w);
      push(w_ijk, candidate);
      ++stats_.relaxed;
    }
  }

  void pushNeighboursWithSites(const openvdb::Coord& ijk, bool inside) {
    for (const openvdb::Coord& step : kNeighbours) {
      EsdfVoxel n;
      bool known;
      if (read(ijk + step, n, known) && n.has_site && (known ? n.inside == inside : !inside))
        push(ijk + step, n.magnitude());
    }
  }

  struct RaiseItem {
    openvdb::Coord from, site;
  };
  openvdb::tree::ValueAccessor<EsdfGrid::TreeType> values_;
  openvdb::tree::ValueAccessor<const EsdfGrid::TreeType> sites_;
  float max_voxels_;
  UpdateStats& stats_;
  std::vector<openvdb::Coord> seeds_;
  std::vector<std::vector<openvdb::Coord>> buckets_;
  std::size_t current_ = 0;  // the bucket lower() is working through
  std::vector<RaiseItem> raise_;
  std::vector<openvdb::Coord> orphans_;
};

EsdfVoxel siteVoxel(bool inside, uint8_t site_distance) {
  EsdfVoxel v;
  v.inside = inside;
  v.has_site = true;
  v.is_site = true;
  v.site_distance = site_distance;
  return v;
}

EsdfVoxel knownVoxel(bool inside) {
  EsdfVoxel v;
  v.inside = inside;
  return v;
}

}  // namespace

EsdfMap::EsdfMap(double voxel_size, EsdfParams params)
    : voxel_size_(voxel_size),
      params_(params),
      max_voxels_(static_cast<float>(params.max_distance / voxel_size)),
      grid_(EsdfGrid::create(0)) {
  grid_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size));
  grid_->setName("esdf");
}

void EsdfMap::clear() {
  grid_->clear();
  surfaces_.clear();
}

UpdateStats EsdfMap::apply(const MapChanges& changes) {
  UpdateStats stats;
  stats.leaves = changes.leaves.size();
  stats.rebuilt = changes.all;
  if (changes.all) clear();
  const Classifier classify(voxel_size_, params_);
  Waves waves(*grid_, max_voxels_, stats);

  using Leaf = Waves::Leaf;
  Classified now[kLeafVoxels];
  for (const ChangedLeaf& leaf : changes.leaves) {
    bool any_known = false;
    for (int n = 0; n < kLeafVoxels; ++n) any_known |= (now[n] = classify(leaf, n)).known;
    Leaf* field = waves.probeLeaf(leaf.origin);
    const bool fresh = field == nullptr;
    if (fresh) {
      if (!any_known) continue;
      field = waves.touchLeaf(leaf.origin);
    }
    for (int n = 0; n < kLeafVoxels; ++n) {
      const Classified& c = now[n];
      const openvdb::Coord ijk = leaf.origin + localCoord(n);
      const auto offset = static_cast<openvdb::Index>(n);
      const EsdfVoxel old = unpackEsdf(field->getValue(offset));
      const bool was_known = field->isValueOn(offset);
      if (!c.known) {
        // Unknown voxels of a new leaf are ways through for the free side's wave.
        if (fresh) waves.addOrphan(ijk);
        if (!was_known) continue;
        if (old.is_site) waves.addRaise(ijk), ++stats.sites_removed;
        field->setValueOff(offset, packEsdf(knownVoxel(false)));
        waves.addOrphan(ijk);
        continue;
      }
      if (!was_known && !c.inside && !c.site && old.has_site) {
        field->setValueOn(offset, packEsdf(old));  // its site, found through unknown space, stays
        continue;
      }
      if (was_known && old.inside == c.inside) {
        if (c.site && old.is_site) {
          const int change = int(c.site_distance) - int(old.site_distance);
          if (change == 0) continue;
          field->setValueOn(offset, packEsdf(siteVoxel(c.inside, c.site_distance)));
          if (change < -kSiteDistanceTolerance) {
            waves.addLower(ijk), ++stats.sites_added;
          } else if (change > kSiteDistanceTolerance) {
            // Farther from the surface: what pointed at it may now be nearer to another site.
            waves.addRaise(ijk), waves.addLower(ijk), ++stats.sites_removed;
          }
        } else if (c.site) {
          field->setValueOn(offset, packEsdf(siteVoxel(c.inside, c.site_distance)));
          waves.addLower(ijk), ++stats.sites_added;
        } else if (old.is_site) {
          field->setValueOn(offset, packEsdf(knownVoxel(c.inside)));
          waves.addRaise(ijk), waves.addOrphan(ijk), ++stats.sites_removed;
        }
        continue;
      }
      // Newly observed, or it changed sides.
      if (old.is_site) waves.addRaise(ijk), ++stats.sites_removed;
      if (c.site) {
        field->setValueOn(offset, packEsdf(siteVoxel(c.inside, c.site_distance)));
        waves.addLower(ijk), ++stats.sites_added;
      } else {
        field->setValueOn(offset, packEsdf(knownVoxel(c.inside)));
        waves.addOrphan(ijk);
      }
    }
    surfaces_.setLeaf(leaf.origin, classify.surfacePoints(leaf));
  }

  waves.raise();
  waves.seedOrphans();
  waves.lower();
  revision_ = changes.revision;
  return stats;
}

}  // namespace semfuse::esdf
