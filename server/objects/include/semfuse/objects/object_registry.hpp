#pragma once
// Object ids that stay with the objects: each grouping of the surface (grouping.hpp) is matched to
// the previous one by the surface voxels they share, so an object keeps its id across queries and
// while the map grows, and the registry says when objects appear, merge, split or vanish.
//
// Matching: every new group counts the voxels it shares with each previous id (a voxel that was
// not on the surface last time takes the id of a face neighbour that was: surfaces settle by a
// voxel as evidence accumulates). Pairs are taken in order of shared voxels, each id and each
// group at most once, when they share at least a fifth of the smaller of the two. A group left
// without an id gets a new one: split from the id it shares most with when that went to another
// group, else appeared. An id left without a group merged into the group that took most of its
// voxels, else vanished. Fragments get ids too, but events name an id only once it has been an
// object: a fragment that grows into an object appears then.
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <openvdb/openvdb.h>

#include "semfuse/core/object_events.hpp"
#include "semfuse/objects/grouping.hpp"
#include "semfuse/objects/surface_voxels.hpp"

namespace semfuse::objects {

class ObjectRegistry {
 public:
  struct Assignment {
    std::vector<uint32_t> ids;  // per group of the grouping
    std::vector<ObjectEvent> events;
    // The id of every surface voxel (0 elsewhere): which object a point of the surface is on.
    std::shared_ptr<const openvdb::Int32Tree> id_tree;
  };

  Assignment assign(const SurfaceVoxels& surface, const Grouping& grouping);
  // Forgets every id (their objects vanish at the next assignment, with events).
  void clear();

 private:
  struct Known {
    uint64_t voxels = 0;
    LabelId label = kUnlabeled;
    bool announced = false;  // an event has named it as an object
  };
  std::shared_ptr<const openvdb::Int32Tree> ids_;  // of the last assignment
  std::unordered_map<uint32_t, Known> known_;
  uint32_t next_id_ = 1;
};

}  // namespace semfuse::objects
