#include "semfuse/objects/object_registry.hpp"

#include <algorithm>
#include <map>
#include <tuple>

#include <tbb/parallel_for.h>

namespace semfuse::objects {
namespace {

using IdLeaf = openvdb::Int32Tree::LeafNodeType;

// A shared count is substantial when it is at least this share of the smaller side.
constexpr double kSubstantialShare = 0.2;

// The previous id of a surface voxel: its own, else a face neighbour's.
uint32_t previousId(const openvdb::tree::ValueAccessor<const openvdb::Int32Tree>& ids, const openvdb::Coord& ijk) {
  if (const int32_t id = ids.getValue(ijk); id > 0) return static_cast<uint32_t>(id);
  static const openvdb::Coord kFaces[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const openvdb::Coord& face : kFaces)
    if (const int32_t id = ids.getValue(ijk + face); id > 0) return static_cast<uint32_t>(id);
  return 0;
}

std::shared_ptr<const openvdb::Int32Tree> idTree(const SurfaceVoxels& surface, const Grouping& grouping,
                                                 const std::vector<uint32_t>& ids) {
  auto tree = std::make_shared<openvdb::Int32Tree>(surface.indexTree(), 0, openvdb::TopologyCopy());
  std::vector<IdLeaf*> leaves;
  tree->getNodes(leaves);
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t l) {
    IdLeaf& leaf = *leaves[l];
    const auto* index = surface.indexTree().probeConstLeaf(leaf.origin());
    for (auto it = leaf.beginValueOn(); it; ++it)
      it.setValue(static_cast<int32_t>(ids[grouping.group_of[index->getValue(it.pos())]]));
  });
  return tree;
}

}  // namespace

void ObjectRegistry::clear() { ids_.reset(); }

ObjectRegistry::Assignment ObjectRegistry::assign(const SurfaceVoxels& surface, const Grouping& grouping) {
  const std::size_t group_count = grouping.groups.size();
  // Voxels each group shares with each previous id.
  std::map<std::pair<int32_t, uint32_t>, uint64_t> shared;
  if (ids_) {
    openvdb::tree::ValueAccessor<const openvdb::Int32Tree> previous(*ids_);
    // Neighbouring voxels mostly share group and id: count runs, look the map up once per run.
    std::pair<int32_t, uint32_t> run{-1, 0};
    uint64_t run_length = 0;
    for (std::size_t i = 0; i < surface.size(); ++i) {
      const std::pair<int32_t, uint32_t> key{grouping.group_of[i], previousId(previous, surface[i].ijk)};
      if (key != run) {
        if (run.second != 0) shared[run] += run_length;
        run = key;
        run_length = 0;
      }
      ++run_length;
    }
    if (run.second != 0) shared[run] += run_length;
  }
  std::vector<std::tuple<uint64_t, int32_t, uint32_t>> pairs;  // (shared, group, id)
  for (const auto& [key, count] : shared) {
    if (!known_.count(key.second)) continue;
    const uint64_t smaller = std::min<uint64_t>(grouping.groups[key.first].voxel_count, known_[key.second].voxels);
    if (count >= kSubstantialShare * static_cast<double>(smaller)) pairs.emplace_back(count, key.first, key.second);
  }
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) { return std::get<0>(a) > std::get<0>(b); });

  Assignment out;
  out.ids.assign(group_count, 0);
  std::unordered_map<uint32_t, int32_t> group_of_id;
  for (const auto& [count, group, id] : pairs) {
    if (out.ids[group] != 0 || group_of_id.count(id)) continue;
    out.ids[group] = id;
    group_of_id[id] = group;
  }

  // The id each group shares most with, and the group each previous id shares most with.
  std::vector<std::pair<uint64_t, uint32_t>> best_id(group_count, {0, 0});
  std::unordered_map<uint32_t, std::pair<uint64_t, int32_t>> best_group;
  for (const auto& [count, group, id] : pairs) {
    if (count > best_id[group].first) best_id[group] = {count, id};
    auto& b = best_group[id];
    if (count > b.first) b = {count, group};
  }

  std::unordered_map<uint32_t, Known> next;
  std::map<uint32_t, ObjectEvent> splits, merges;  // by the id that goes on
  for (std::size_t g = 0; g < group_count; ++g) {
    const Group& group = grouping.groups[g];
    const bool is_object = !group.fragment;
    uint32_t& id = out.ids[g];
    bool split = false;
    uint32_t parent = 0;
    if (id == 0) {
      id = next_id_++;
      parent = best_id[g].second;
      split = parent != 0 && group_of_id.count(parent);
    }
    Known known = known_.count(id) ? known_[id] : Known{};
    known.voxels = group.voxel_count;
    known.label = group.label;
    if (is_object && !known.announced) {
      known.announced = true;
      if (split && known_[parent].announced) {
        ObjectEvent& event = splits[parent];
        event.kind = ObjectEventKind::kSplit;
        event.id = parent;
        event.label = grouping.groups[group_of_id[parent]].label;
        event.others.push_back(id);
      } else {
        out.events.push_back({ObjectEventKind::kAppeared, id, group.label, {}});
      }
    }
    next[id] = known;
  }
  for (const auto& [id, known] : known_) {
    if (group_of_id.count(id) || !known.announced) continue;
    const auto best = best_group.find(id);
    if (best != best_group.end() && out.ids[best->second.second] != 0) {
      const int32_t group = best->second.second;
      const uint32_t survivor = out.ids[group];
      ObjectEvent& event = merges[survivor];
      event.kind = ObjectEventKind::kMerged;
      event.id = survivor;
      event.label = grouping.groups[group].label;
      event.others.push_back(id);
    } else {
      out.events.push_back({ObjectEventKind::kVanished, id, known.label, {}});
    }
  }
  for (auto& [id, event] : merges) {
    std::sort(event.others.begin(), event.others.end());
    out.events.push_back(std::move(event));
  }
  for (auto& [id, event] : splits) out.events.push_back(std::move(event));

  known_ = std::move(next);
  ids_ = idTree(surface, grouping, out.ids);
  out.id_tree = ids_;
  return out;
}

}  // namespace semfuse::objects
