// LabeledVolume::catchUpWith: a copy of the map brought up to date leaf by leaf. The server hands
// queries read-only copies of the map (objects, meshes, region summaries); copying a 1 cm room
// whole (over 100 MiB) for every query after a frame cost more than the fusion itself.
#include <vector>

#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::volume {
namespace {

// The leaf at `origin` of `to` becomes what `from` holds there: a copy of its leaf, or its tile
// (the background, or an observed-free tile) when it has none.
template <class Grid>
void copyLeaf(const typename Grid::TreeType& from, typename Grid::TreeType& to, const openvdb::Coord& origin) {
  using Leaf = typename Grid::TreeType::LeafNodeType;
  if (const Leaf* leaf = from.probeConstLeaf(origin)) {
    to.addLeaf(new Leaf(*leaf));
    return;
  }
  typename Grid::ValueType value;
  const bool on = from.probeValue(origin, value);
  if (to.probeConstLeaf(origin) || to.isValueOn(origin) != on) to.addTile(1, origin, value, on);
}

// `to` follows `from` at the changed leaves; a grid that appeared in `from` is copied whole.
template <class Grid>
void catchUpGrid(const typename Grid::Ptr& from, typename Grid::Ptr& to, const std::vector<openvdb::Coord>& leaves) {
  if (!from) {
    to.reset();
    return;
  }
  if (!to) {
    to = from->deepCopy();
    return;
  }
  for (const openvdb::Coord& origin : leaves) copyLeaf<Grid>(from->tree(), to->tree(), origin);
}

}  // namespace

void LabeledVolume::catchUpWith(const LabeledVolume& source) {
  const LeafChanges changes = source.changesSince(revision_);
  if (changes.all) {
    *this = source.deepCopy();
    return;
  }
  catchUpGrid<GeometryGrid>(source.geometry_, geometry_, changes.leaves);
  catchUpGrid<ColorGrid>(source.color_, color_, changes.leaves);
  catchUpGrid<LabelSidecarGrid>(source.label_sidecar_, label_sidecar_, changes.leaves);
  catchUpGrid<InstanceGrid>(source.instances_, instances_, changes.leaves);
  catchUpGrid<FreeSpaceGrid>(source.free_space_, free_space_, changes.leaves);
  next_instance_id_ = source.next_instance_id_;
  instances_apart_ = source.instances_apart_;
  frames_integrated_ = source.frames_integrated_;
  leaf_revisions_ = std::make_shared<RevisionTree>(*source.leaf_revisions_);
  revision_ = source.revision_;
  replaced_at_ = source.replaced_at_;
}

}  // namespace semfuse::volume
