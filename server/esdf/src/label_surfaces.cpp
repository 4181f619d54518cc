#include "semfuse/esdf/label_surfaces.hpp"

#include <algorithm>

namespace semfuse::esdf {

void LabelSurfaces::setLeaf(const openvdb::Coord& origin, std::vector<SurfacePoint> points) {
  auto old = by_leaf_.find(origin);
  if (old == by_leaf_.end() && points.empty()) return;
  if (old != by_leaf_.end()) {
    for (const SurfacePoint& p : old->second) {
      auto& leaves = leaves_of_label_[p.label];
      if (auto it = leaves.find(origin); it != leaves.end() && --it->second == 0) leaves.erase(it);
    }
    points_ -= old->second.size();
  }
  ++revision_;
  if (points.empty()) {
    by_leaf_.erase(old);
    return;
  }
  for (const SurfacePoint& p : points) ++leaves_of_label_[p.label][origin];
  points_ += points.size();
  by_leaf_[origin] = std::move(points);
}

void LabelSurfaces::clear() {
  by_leaf_.clear();
  leaves_of_label_.clear();
  points_ = 0;
  ++revision_;
}

std::vector<SurfacePoint> LabelSurfaces::gather(const std::vector<LabelId>& labels) const {
  std::vector<LabelId> wanted = labels;
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  // A leaf holding several of the labels is read once.
  std::unordered_map<openvdb::Coord, bool, KeyHash> leaves;
  for (LabelId label : wanted)
    if (auto it = leaves_of_label_.find(label); it != leaves_of_label_.end())
      for (const auto& entry : it->second) leaves.emplace(entry.first, true);
  std::vector<SurfacePoint> out;
  for (const auto& entry : leaves)
    for (const SurfacePoint& p : by_leaf_.at(entry.first))
      if (std::binary_search(wanted.begin(), wanted.end(), p.label)) out.push_back(p);
  return out;
}

std::size_t LabelSurfaces::memoryBytes() const {
  return points_ * sizeof(SurfacePoint) + by_leaf_.size() * (sizeof(openvdb::Coord) + 3 * sizeof(void*) + 32);
}

}  // namespace semfuse::esdf
