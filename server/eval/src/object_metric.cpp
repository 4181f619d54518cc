#include "object_metric.hpp"

#include <algorithm>

#include <tbb/parallel_for.h>

namespace semfuse::eval {

ClassCounts& ClassCounts::operator+=(const ClassCounts& other) {
  true_objects += other.true_objects;
  found_objects += other.found_objects;
  matched += other.matched;
  return *this;
}

std::vector<uint32_t> trueInstances(const objects::SurfaceVoxels& surface, const synthetic::LabeledScene& scene,
                                    double max_distance) {
  std::vector<uint32_t> truth(surface.size(), 0);
  tbb::parallel_for(std::size_t{0}, surface.size(), [&](std::size_t i) {
    const synthetic::NearestSurface nearest = scene.nearestSurface(surface.position(i));
    if (std::abs(nearest.signed_distance) <= max_distance) truth[i] = scene.instanceOf(nearest.object);
  });
  return truth;
}

std::map<uint32_t, LabelId> instanceLabels(const synthetic::LabeledScene& scene) {
  std::map<uint32_t, LabelId> labels;
  for (std::size_t i = 0; i < scene.objects().size(); ++i) labels[scene.instanceOf(i)] = scene.objects()[i].label;
  return labels;
}

ObjectScore scoreObjects(const objects::SurfaceVoxels& surface, const objects::Grouping& grouping,
                         const std::vector<uint32_t>& truth, const std::map<uint32_t, LabelId>& true_labels,
                         double min_area_m2) {
  std::map<uint32_t, uint64_t> true_voxels;
  std::map<uint32_t, double> true_area;
  std::map<std::pair<int32_t, uint32_t>, uint64_t> shared;  // (group, instance) -> voxels
  for (std::size_t i = 0; i < surface.size(); ++i) {
    if (truth[i] == 0) continue;
    ++true_voxels[truth[i]];
    true_area[truth[i]] += surface[i].area_m2;
    ++shared[{grouping.group_of[i], truth[i]}];
  }
  ObjectScore score;
  score.instance_of_group.assign(grouping.groups.size(), 0);
  for (const auto& [instance, area] : true_area) {
    if (area < min_area_m2) continue;
    const auto label = true_labels.find(instance);
    if (label == true_labels.end()) continue;
    ++score.classes[label->second].true_objects;
    score.best_iou[instance] = 0.0;
  }
  for (const objects::Group& group : grouping.groups)
    if (!group.fragment) ++score.classes[group.label].found_objects;
  for (const auto& [key, count] : shared) {
    const auto& [g, instance] = key;
    const objects::Group& group = grouping.groups[g];
    if (group.fragment || !score.best_iou.count(instance)) continue;
    const double iou = double(count) / double(group.voxel_count + true_voxels[instance] - count);
    score.best_iou[instance] = std::max(score.best_iou[instance], iou);
    if (iou >= 0.5 && true_labels.at(instance) == group.label) {
      score.instance_of_group[g] = instance;
      ++score.classes[group.label].matched;
    }
  }
  for (const auto& [label, counts] : score.classes) score.total += counts;
  return score;
}

}  // namespace semfuse::eval
