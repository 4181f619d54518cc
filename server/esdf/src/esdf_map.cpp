#include "semfuse/esdf/esdf_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "semfuse/volume/voxel.hpp"
#include "waves.hpp"

namespace semfuse::esdf {
namespace {

constexpr int kLeafDim = volume::LabeledVolume::kLeafDim;
constexpr int kLeafVoxels = volume::LabeledVolume::kLeafVoxels;

// A site whose distance to the surface changed by less than this (1/255 voxel units, about 0.1
// voxel) keeps the voxels that point at it as they are: their copies of its distance are then off
// by at most that much until a wave passes them. A larger change re-propagates.
constexpr int kSiteDistanceTolerance = 26;

using detail::leafOffset;
using detail::localCoord;

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
        c.site_distance = static_cast<uint8_t>(std::lround(crossing.distance * 255.0f));
      }
    } else if (leaf.observed_free[n]) {
      c.known = true;
    }
    return c;
  }

  // Labeled surface points: for every free-side site with a label, the zero crossing on its
  // nearest crossing edge (a point of the surface: the plane's nearest point would cut the corners
  // of boxes).
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
  // The surface near a site as the plane through the zero crossings on its edges, one per axis
  // (the nearer one where both edges of an axis cross): with crossings at fractions a, b, c of a
  // voxel along the axes, the plane lies 1 / sqrt(1/a^2 + 1/b^2 + 1/c^2) from the voxel's centre
  // (an axis without a crossing adds nothing). The nearest crossing alone overestimates the
  // distance to an oblique surface by up to sqrt(3) (a sphere's rim, a rotated box's faces).
  struct Crossing {
    int axis = -1;  // the nearest crossing's edge; -1: no neighbour across the surface
    int direction = 0;
    float fraction = 1.0f;
    float distance = 1.0f;  // to the plane, voxels
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
    const openvdb::Coord local = localCoord(n);
    const bool negative = tsdf < 0.0f;
    float fraction[3] = {0.0f, 0.0f, 0.0f};  // 0: no crossing along the axis
    int direction[3] = {0, 0, 0};
    Crossing best;
    for (int axis = 0; axis < 3; ++axis)
      for (int step : {-1, 1}) {
        float other;
        if (!neighbourTsdf(leaf, local, axis, step, other) || (other < 0.0f) == negative) continue;
        const float f = std::abs(tsdf) / (std::abs(tsdf) + std::abs(other));
        if (direction[axis] == 0 || f < fraction[axis]) fraction[axis] = f, direction[axis] = step;
        if (best.axis < 0 || f < best.fraction) best = {axis, step, f, f};
      }
    if (best.axis < 0) return best;
    if (best.fraction <= 0.0f) return best;  // the surface passes through the centre
    float inverse_squares = 0.0f;
    for (int axis = 0; axis < 3; ++axis)
      if (direction[axis] != 0) inverse_squares += 1.0f / (fraction[axis] * fraction[axis]);
    best.distance = 1.0f / std::sqrt(inverse_squares);
    return best;
  }

  float voxel_, min_weight_;
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
      grid_(EsdfGrid::create(0)),
      waves_(std::make_unique<detail::Waves>(grid_->tree(), max_voxels_)) {
  grid_->setTransform(openvdb::math::Transform::createLinearTransform(voxel_size));
  grid_->setName("esdf");
}

EsdfMap::~EsdfMap() = default;

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
  detail::Waves& waves = *waves_;
  openvdb::tree::ValueAccessor<EsdfGrid::TreeType> leaves(grid_->tree());

  using Leaf = detail::FieldLeaf;
  Classified now[kLeafVoxels];
  for (const ChangedLeaf& leaf : changes.leaves) {
    bool any_known = false;
    for (int n = 0; n < kLeafVoxels; ++n) any_known |= (now[n] = classify(leaf, n)).known;
    Leaf* field = leaves.probeLeaf(leaf.origin);
    const bool fresh = field == nullptr;
    if (fresh) {
      if (!any_known) continue;
      field = leaves.touchLeaf(leaf.origin);
    }
    for (int n = 0; n < kLeafVoxels; ++n) {
      const Classified& c = now[n];
      const detail::VoxelRef voxel{field, static_cast<uint32_t>(n)};
      const auto offset = static_cast<openvdb::Index>(n);
      const EsdfVoxel old = unpackEsdf(field->getValue(offset));
      const bool was_known = field->isValueOn(offset);
      if (!c.known) {
        // Unknown voxels of a new leaf are ways through for the free side's wave.
        if (fresh) waves.addOrphan(voxel);
        if (!was_known) continue;
        if (old.is_site) waves.addRaise(voxel), ++stats.sites_removed;
        field->setValueOff(offset, packEsdf(knownVoxel(false)));
        waves.addOrphan(voxel);
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
            waves.addLower(voxel), ++stats.sites_added;
          } else if (change > kSiteDistanceTolerance) {
            // Farther from the surface: what pointed at it may now be nearer to another site.
            waves.addRaise(voxel), waves.addLower(voxel), ++stats.sites_removed;
          }
        } else if (c.site) {
          field->setValueOn(offset, packEsdf(siteVoxel(c.inside, c.site_distance)));
          waves.addLower(voxel), ++stats.sites_added;
        } else if (old.is_site) {
          field->setValueOn(offset, packEsdf(knownVoxel(c.inside)));
          waves.addRaise(voxel), waves.addOrphan(voxel), ++stats.sites_removed;
        }
        continue;
      }
      // Newly observed, or it changed sides.
      if (old.is_site) waves.addRaise(voxel), ++stats.sites_removed;
      if (c.site) {
        field->setValueOn(offset, packEsdf(siteVoxel(c.inside, c.site_distance)));
        waves.addLower(voxel), ++stats.sites_added;
      } else {
        field->setValueOn(offset, packEsdf(knownVoxel(c.inside)));
        waves.addOrphan(voxel);
      }
    }
    surfaces_.setLeaf(leaf.origin, classify.surfacePoints(leaf));
  }

  waves.run(stats);
  revision_ = changes.revision;
  return stats;
}

}  // namespace semfuse::esdf
