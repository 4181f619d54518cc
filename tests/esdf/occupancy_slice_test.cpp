// Occupancy slices of the fused room against its floor plan, inflation, bounds and unknown cells.
#include <cmath>
#include <cstdio>
#include <string>
#include <variant>

#include <gtest/gtest.h>

#include "field_checks.hpp"
#include "fused_room.hpp"
#include "semfuse/esdf/distance_queries.hpp"

namespace semfuse::esdf::testing {
namespace {

// The room's floor plan in the band: a cell is occupied when the surface passes within half a
// voxel of, or an obstacle holds, one of its column's voxel centres within [z_min, z_max].
// Measurable: a depth camera can see some voxel of the column, i.e. one lies within the
// truncation of a surface; the columns of a tall object's inside farther than that from its faces
// (the cabinet's) are unknown to any TSDF and left out of the comparison, and so are the occupied
// cells none of whose occupied voxels has its nearest surface observed by the TSDF at all (the
// cabinet's corner with the +x wall: no view looks into it): no map can know a face that no
// camera looked at. Both kinds must come out unknown or occupied, never free.
// Legs thinner than two voxels (4-6 cm across at 5 cm) leave no reliable zero crossing in the
// TSDF; cells occupied by nothing else are left out too.
struct PlanCell {
  bool occupied = false;
  bool measurable = false;
  bool seen = false;  // occupied by a voxel whose nearest surface the TSDF observed
  bool sub_voxel_only = false;
};
bool subVoxel(const synthetic::SceneObject& object) {
  const auto* cylinder = std::get_if<synthetic::UprightCylinder>(&object.shape);
  return cylinder && 2 * cylinder->radius < 2 * kVoxel;
}
// Whether a point lies outside every solid.
bool outsideAll(const synthetic::LabeledScene& scene, const Eigen::Vector3d& p) {
  for (const auto& object : scene.objects())
    if (synthetic::signedDistance(object.shape, p) <= 1e-6) return false;
  return true;
}
// Within `radius` of the free space around the solids: of the union, not of one solid, since a
// face that touches another solid (the cabinet's back against the wall) is no surface at all.
bool nearFreeSpace(const synthetic::LabeledScene& scene, const Eigen::Vector3d& p, double radius) {
  if (outsideAll(scene, p)) return true;
  for (int x = -1; x <= 1; ++x)
    for (int y = -1; y <= 1; ++y)
      for (int z = -1; z <= 1; ++z)
        if ((x || y || z) && outsideAll(scene, p + Eigen::Vector3d(x, y, z).normalized() * radius)) return true;
  return false;
}
PlanCell analyticCell(const FusedRoom& room, double x, double y, double z_min, double z_max, double truncation) {
  const synthetic::LabeledScene& scene = room.scene;
  PlanCell cell;
  for (int iz = static_cast<int>(std::ceil(z_min / kVoxel - 1e-9)); iz * kVoxel <= z_max + 1e-9; ++iz) {
    const Eigen::Vector3d p(x, y, iz * kVoxel);
    bool occupied = false;
    for (const auto& object : scene.objects()) {
      if (synthetic::signedDistance(object.shape, p) >= 0.5 * kVoxel) continue;
      cell.sub_voxel_only = (cell.occupied ? cell.sub_voxel_only : true) && subVoxel(object);
      cell.occupied = occupied = true;
    }
    const bool measurable = nearFreeSpace(scene, p, truncation);
    cell.measurable |= measurable;
    cell.seen |= occupied && measurable && room.volume->voxelAt(nearestTruePoint(scene, p)).observed();
  }
  return cell;
}

OccupancyRequest roomBand() {
  OccupancyRequest request;
  request.z_min = 0.15;
  request.z_max = 0.6;
  request.bounds = SliceBounds{{-2.5, -2.0}, {2.5, 2.0}};  // the room's inner walls
  return request;
}

TEST(OccupancySlice, MatchesTheRoomsFloorPlan) {
  const FusedRoom& room = fusedRoom();
  const OccupancyRequest request = roomBand();
  const OccupancyGrid grid = occupancySlice(*room.esdf, request);
  // One cell per voxel column from wall to wall, cell (0, 0) centred on the -x, -y corner.
  ASSERT_EQ(grid.width, static_cast<int>(std::lround(5.0 / kVoxel)) + 1);
  ASSERT_EQ(grid.height, static_cast<int>(std::lround(4.0 / kVoxel)) + 1);
  EXPECT_NEAR(grid.origin.x(), -2.5 - 0.5 * kVoxel, 1e-9);
  EXPECT_NEAR(grid.origin.y(), -2.0 - 0.5 * kVoxel, 1e-9);
  EXPECT_DOUBLE_EQ(grid.resolution, kVoxel);
  const double truncation = room.volume->params().truncation;
  std::size_t both = 0, either = 0, free_cells = 0, free_but_occupied = 0, unknown = 0, unmeasurable = 0, unseen = 0,
              legs = 0;
  for (int row = 0; row < grid.height; ++row)
    for (int col = 0; col < grid.width; ++col) {
      const double x = grid.origin.x() + (col + 0.5) * kVoxel, y = grid.origin.y() + (row + 0.5) * kVoxel;
      const PlanCell plan = analyticCell(room, x, y, request.z_min, request.z_max, truncation);
      const int8_t cell = grid.cells[static_cast<std::size_t>(row) * grid.width + col];
      if (!plan.measurable) {
        ++unmeasurable;
        EXPECT_NE(cell, kCellFree);
        continue;
      }
      if (plan.sub_voxel_only) {
        ++legs;
        continue;
      }
      if (plan.occupied && !plan.seen) {
        ++unseen;
        EXPECT_NE(cell, kCellFree);
        continue;
      }
      const bool truth = plan.occupied;
      const bool occupied = cell == kCellOccupied;
      both += truth && occupied;
      either += truth || occupied;
      if (cell == kCellFree) ++free_cells, free_but_occupied += truth;
      unknown += cell == kCellUnknown;
    }
  const double iou = static_cast<double>(both) / static_cast<double>(either);
  std::printf(
      "occupied IoU %.3f (%zu of %zu); %zu free cells, %zu of them occupied in the plan; %zu unknown; %zu inside a "
      "tall object, %zu beside a face no view saw and %zu only a leg's, left out\n",
      iou, both, either, free_cells, free_but_occupied, unknown, unmeasurable, unseen, legs);
  // 0.955. Of the 42 cells that differ from the plan, 18 are free cells beside the chairs' 4 cm
  // backrests, whose voxel 3 cm off one face lies 7 cm behind the other, within the 10 cm
  // truncation and before the integrator's weight drops off, so views of that face integrate it
  // as inside; 10 are cells of the big sphere's far rim, seen only at grazing angles; 5 are
  // columns just inside the cabinet's +y side, observed by no view at that height (unknown); the
  // other 9 lie at the edges of the boxes and the cabinet, whose faces pass 1-3 cm from the
  // column's voxel centres, against the plan's threshold of half a voxel (2.5 cm).
  EXPECT_GE(iou, 0.95);
  EXPECT_GT(free_cells, 5000u);
  EXPECT_LE(free_but_occupied, free_cells / 200);
}

TEST(OccupancySlice, InflationMarksFreeCellsNearObstacles) {
  const FusedRoom& room = fusedRoom();
  OccupancyRequest request = roomBand();
  const OccupancyGrid plain = occupancySlice(*room.esdf, request);
  request.inflation_radius = 0.2;
  const OccupancyGrid inflated = occupancySlice(*room.esdf, request);
  ASSERT_EQ(plain.cells.size(), inflated.cells.size());
  std::size_t newly = 0;
  for (std::size_t i = 0; i < plain.cells.size(); ++i) {
    if (plain.cells[i] != kCellFree) {
      EXPECT_EQ(inflated.cells[i], plain.cells[i]);  // occupied and unknown cells stay as they were
      continue;
    }
    if (inflated.cells[i] != kCellInflated) continue;
    ++newly;
    // Within 0.2 m of an occupied cell.
    const int row = static_cast<int>(i) / plain.width, col = static_cast<int>(i) % plain.width;
    const int reach = static_cast<int>(std::floor(0.2 / kVoxel + 1e-9));
    bool near = false;
    for (int dr = -reach; dr <= reach && !near; ++dr)
      for (int dc = -reach; dc <= reach && !near; ++dc) {
        const int r = row + dr, c = col + dc;
        near = (dr * dr + dc * dc) * kVoxel * kVoxel <= 0.2 * 0.2 + 1e-9 && r >= 0 && c >= 0 && r < plain.height &&
               c < plain.width && plain.cells[static_cast<std::size_t>(r) * plain.width + c] == kCellOccupied;
      }
    EXPECT_TRUE(near) << "cell " << col << "," << row;
  }
  EXPECT_GT(newly, 500u);
  // The cell right next to the +x wall's inner face... and the open centre-left of the room.
  auto cellAt = [&](const OccupancyGrid& g, double x, double y) {
    const int col = static_cast<int>(std::floor((x - g.origin.x()) / g.resolution));
    const int row = static_cast<int>(std::floor((y - g.origin.y()) / g.resolution));
    return g.cells[static_cast<std::size_t>(row) * g.width + col];
  };
  EXPECT_EQ(cellAt(inflated, -1.6, -0.6), kCellFree);       // 0.6 m from anything in the band
  EXPECT_EQ(cellAt(inflated, -2.35, -0.6), kCellInflated);  // 0.15 m from the -x wall
}

TEST(OccupancySlice, BoundsOutsideTheObservedRoomAreUnknown) {
  const FusedRoom& room = fusedRoom();
  OccupancyRequest request;
  request.z_min = 0.3;
  request.z_max = 0.3;                                    // one voxel layer
  request.bounds = SliceBounds{{3.0, -1.0}, {4.0, 1.0}};  // behind the +x wall
  const OccupancyGrid grid = occupancySlice(*room.esdf, request);
  ASSERT_EQ(grid.cells.size(),
            static_cast<std::size_t>((std::lround(1.0 / kVoxel) + 1) * (std::lround(2.0 / kVoxel) + 1)));
  for (int8_t cell : grid.cells) EXPECT_EQ(cell, kCellUnknown);
  // Without bounds: the field's observed extent.
  request.bounds.reset();
  const OccupancyGrid whole = occupancySlice(*room.esdf, request);
  EXPECT_GE(whole.width * kVoxel, 5.0);
  EXPECT_GE(whole.height * kVoxel, 4.0);
  EXPECT_EQ(occupancyCellCount(*room.esdf, request), whole.cells.size());
  // An empty field has nothing to slice.
  const EsdfMap empty(kVoxel, roomEsdfParams());
  EXPECT_EQ(occupancySlice(empty, request).cells.size(), 0u);
}

}  // namespace
}  // namespace semfuse::esdf::testing
