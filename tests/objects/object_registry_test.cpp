// Object ids across groupings: an object keeps its id while its surface changes, and the registry
// names what happened when objects split, merge or vanish. The surface is a strip of 100 voxels.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "semfuse/objects/object_figures.hpp"
#include "semfuse/objects/object_registry.hpp"

namespace semfuse::objects {
namespace {

constexpr double kVoxel = 0.02;

SurfaceVoxels strip(int begin, int end) {
  std::vector<SurfaceVoxel> voxels;
  for (int x = begin; x < end; ++x) {
    SurfaceVoxel v;
    v.ijk = openvdb::Coord(x, 0, 0);
    v.normal = Eigen::Vector3f::UnitZ();
    v.area_m2 = static_cast<float>(kVoxel * kVoxel);
    v.label = 3;
    voxels.push_back(v);
  }
  return SurfaceVoxels(kVoxel, std::move(voxels));
}

// Voxel i of the strip goes to group cut[i]; groups are objects.
Grouping groupsOf(const SurfaceVoxels& surface, const std::vector<int>& cuts) {
  Grouping g;
  if (surface.size() == 0) return g;
  g.groups.resize(cuts.size() + 1);
  for (auto& group : g.groups) group.label = 3;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    int group = 0;
    while (group < static_cast<int>(cuts.size()) && surface[i].ijk.x() >= cuts[group]) ++group;
    g.group_of.push_back(group);
    ++g.groups[group].voxel_count;
  }
  return g;
}

TEST(ObjectRegistry, IdsFollowTheSurfaceThroughGrowthSplitAndMerge) {
  ObjectRegistry registry;
  const SurfaceVoxels first = strip(0, 100);
  const auto a = registry.assign(first, groupsOf(first, {}));
  ASSERT_EQ(a.ids.size(), 1u);
  const uint32_t id = a.ids[0];
  ASSERT_EQ(a.events.size(), 1u);
  EXPECT_EQ(a.events[0].kind, ObjectEventKind::kAppeared);
  EXPECT_EQ(a.id_tree->getValue(openvdb::Coord(42, 0, 0)), static_cast<int32_t>(id));

  // The map grows by 20 voxels: the same object, no event.
  const SurfaceVoxels grown = strip(0, 120);
  const auto b = registry.assign(grown, groupsOf(grown, {}));
  EXPECT_EQ(b.ids[0], id);
  EXPECT_TRUE(b.events.empty());

  // It comes apart at x = 80: the larger piece keeps the id, the other is split from it.
  const auto c = registry.assign(grown, groupsOf(grown, {80}));
  ASSERT_EQ(c.ids.size(), 2u);
  EXPECT_EQ(c.ids[0], id);
  const uint32_t piece = c.ids[1];
  EXPECT_NE(piece, id);
  ASSERT_EQ(c.events.size(), 1u);
  EXPECT_EQ(c.events[0].kind, ObjectEventKind::kSplit);
  EXPECT_EQ(c.events[0].id, id);
  EXPECT_EQ(c.events[0].others, std::vector<uint32_t>{piece});

  // Asked again unchanged: the same two ids.
  const auto d = registry.assign(grown, groupsOf(grown, {80}));
  EXPECT_EQ(d.ids, c.ids);
  EXPECT_TRUE(d.events.empty());

  // Whole again: the piece merges into the object that goes on.
  const auto e = registry.assign(grown, groupsOf(grown, {}));
  EXPECT_EQ(e.ids[0], id);
  ASSERT_EQ(e.events.size(), 1u);
  EXPECT_EQ(e.events[0].kind, ObjectEventKind::kMerged);
  EXPECT_EQ(e.events[0].id, id);
  EXPECT_EQ(e.events[0].others, std::vector<uint32_t>{piece});

  // The map is emptied: it vanishes.
  const SurfaceVoxels none = strip(0, 0);
  const auto f = registry.assign(none, groupsOf(none, {}));
  ASSERT_EQ(f.events.size(), 1u);
  EXPECT_EQ(f.events[0].kind, ObjectEventKind::kVanished);
  EXPECT_EQ(f.events[0].id, id);
}

TEST(ObjectFigures, MinimumAreaRectangleOfARotatedRectangle) {
  const double angle = 30.0 * M_PI / 180.0;
  const Eigen::Vector2d u(std::cos(angle), std::sin(angle)), v(-std::sin(angle), std::cos(angle));
  const Eigen::Vector2d centre(1.0, -2.0);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 10; ++j) points.push_back(centre + (-1.0 + 0.1 * i) * u + (-0.5 + 0.1 * j) * v);
  const Rectangle2d r = minimumAreaRectangle(points);
  EXPECT_NEAR(r.center.x(), centre.x(), 1e-9);
  EXPECT_NEAR(r.center.y(), centre.y(), 1e-9);
  const double long_half = r.half_extents.maxCoeff(), short_half = r.half_extents.minCoeff();
  EXPECT_NEAR(long_half, 1.0, 1e-9);
  EXPECT_NEAR(short_half, 0.5, 1e-9);
  // The first axis is one of the rectangle's: parallel to u or to v.
  EXPECT_NEAR(std::max(std::abs(r.axis.dot(u)), std::abs(r.axis.dot(v))), 1.0, 1e-9);
}

}  // namespace
}  // namespace semfuse::objects
