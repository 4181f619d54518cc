#pragma once
// Scores the map's objects against the synthetic room's exact instances, over surface voxels.
//
// Truth: every surface voxel (objects/surface_voxels.hpp) belongs to the instance of the scene's
// solid nearest to its centre, if that solid lies within max_distance. A true instance counts when
// its surface voxels cover at least the minimum object area: one the cameras barely saw cannot be
// found. A found object (a group that is not a fragment) matches a true instance of its own class
// when their voxel sets overlap with IoU >= 0.5, which makes the matching one to one. Per class,
// precision is the share of found objects that match, recall the share of true instances matched.
#include <cstdint>
#include <map>
#include <vector>

#include "semfuse/core/legend.hpp"
#include "semfuse/objects/grouping.hpp"
#include "semfuse/objects/surface_voxels.hpp"
#include "semfuse/synthetic/labeled_scene.hpp"

namespace semfuse::eval {

// The true instance of each surface voxel (0 = no solid within max_distance metres).
std::vector<uint32_t> trueInstances(const objects::SurfaceVoxels& surface, const synthetic::LabeledScene& scene,
                                    double max_distance);
// The class of each of the scene's instances.
std::map<uint32_t, LabelId> instanceLabels(const synthetic::LabeledScene& scene);

struct ClassCounts {
  uint32_t true_objects = 0;   // true instances large enough to count
  uint32_t found_objects = 0;  // objects (not fragments) of the class
  uint32_t matched = 0;        // pairs with IoU >= 0.5
  double precision() const { return found_objects ? double(matched) / found_objects : 1.0; }
  double recall() const { return true_objects ? double(matched) / true_objects : 1.0; }
  ClassCounts& operator+=(const ClassCounts& other);
};

struct ObjectScore {
  std::map<LabelId, ClassCounts> classes;
  ClassCounts total;
  std::vector<uint32_t> instance_of_group;  // per group: the true instance it matches, 0 = none
  std::map<uint32_t, double> best_iou;      // per counted true instance: its best IoU with an object
};

ObjectScore scoreObjects(const objects::SurfaceVoxels& surface, const objects::Grouping& grouping,
                         const std::vector<uint32_t>& truth, const std::map<uint32_t, LabelId>& true_labels,
                         double min_area_m2);

}  // namespace semfuse::eval
