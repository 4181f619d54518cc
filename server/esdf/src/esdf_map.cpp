#include "semfuse/esdf/esdf_map.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "leaf_classifier.hpp"
#include "waves.hpp"

namespace semfuse::esdf {
namespace {

constexpr int kLeafVoxels = volume::LabeledVolume::kLeafVoxels;

// A site whose distance to the surface changed by less than this (1/255 voxel units, about 0.1
// voxel) keeps the voxels that point at it as they are: their copies of its distance are then off
// by at most that much until a wave passes them. A larger change re-propagates.
constexpr int kSiteDistanceTolerance = 26;

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
  detail::Waves& waves = *waves_;
  openvdb::tree::ValueAccessor<EsdfGrid::TreeType> leaves(grid_->tree());

  using Leaf = detail::FieldLeaf;
  // Not kept between updates: a rebuild's would hold megabytes for nothing.
  detail::ClassifiedLeaves classified_leaves;
  classified_leaves.classify(changes.leaves, voxel_size_, params_);
  for (std::size_t i = 0; i < changes.leaves.size(); ++i) {
    const ChangedLeaf& leaf = changes.leaves[i];
    detail::ClassifiedLeaf& classified = classified_leaves.leaves[i];
    const bool any_known = classified.any_known;
    const auto& now = classified.voxels;
    Leaf* field = leaves.probeLeaf(leaf.origin);
    const bool fresh = field == nullptr;
    if (fresh) {
      if (!any_known) continue;
      field = leaves.touchLeaf(leaf.origin);
    }
    for (int n = 0; n < kLeafVoxels; ++n) {
      const detail::Classified& c = now[n];
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
    surfaces_.setLeaf(leaf.origin, std::move(classified.surface));
  }

  waves.run(stats);
  revision_ = changes.revision;
  return stats;
}

}  // namespace semfuse::esdf
