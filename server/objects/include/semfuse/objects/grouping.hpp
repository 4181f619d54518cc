#pragma once
// Grouping of the labeled surface into object instances: what a person would point at.
//
//  1. Patches. Neighbouring surface voxels (surface_voxels.hpp; 26-neighbourhood and two apart
//     along an axis, so a gap of one voxel does not cut) join one patch when they share a label,
//     do not name two panoptic instances seen apart, their normals differ by less than the smooth
//     angle and the step between them is not concave. Patches are smooth pieces: a box's faces,
//     a sphere, a leg.
//  2. Convex unions. Two patches of one label join where most steps across their boundary are
//     convex or flat: the faces of a box become the box, the pieces of a leg the leg. A concave
//     crease (where a box stands on a box, or a leg meets a table top) does not join.
//  3. Parts and supports. Two groups of one label that meet at a concave crease join when the
//     crease lies on no upward face of either (a leg under a table top is part of the table), and
//     stay apart when it lies on one (a box standing on a box is an object of its own). Groups
//     whose panoptic instances agree join whatever the geometry; groups of two instances that a
//     segmentation named as two segments (SurfaceVoxels::instancesSeenApart) never join. Two
//     instances never seen apart (a box's face first seen alone, the rest of the box later) are
//     left to the geometry.
//  4. Fragments. A group smaller than the minimum area joins the object it has the most links
//     with, of its own label if it touches one (label noise, a crease strip, a stray leg piece);
//     one that touches no object stays a fragment.
//  5. Enclosed pieces. A region inside the box of a region of its label twenty times larger joins
//     it: what stands in front of an object cuts pieces off it that share no link with it.
// An object's label is the one most of its area carries.
#include <cstdint>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/objects/object_params.hpp"
#include "semfuse/objects/surface_voxels.hpp"

namespace semfuse::objects {

struct Group {
  LabelId label = kUnlabeled;
  uint64_t voxel_count = 0;
  double area_m2 = 0.0;
  bool fragment = false;  // smaller than min_object_area_m2
  uint32_t instance = 0;  // the panoptic instance most of its voxels name, 0 = none
};

struct Grouping {
  std::vector<int32_t> group_of;  // per surface voxel, an index into groups
  std::vector<Group> groups;      // objects first, largest first; then fragments, largest first
};

Grouping groupSurface(const SurfaceVoxels& surface, const ObjectParams& params);

}  // namespace semfuse::objects
