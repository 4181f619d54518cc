// The distance field's handlers (server/core/src/distance_handlers.*) on a Mapper fed the
// synthetic room, with its DistanceField thread keeping up: what each answers and what it
// refuses, with which code and message; and the field following a reset and a load.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "distance_field.hpp"
#include "distance_handlers.hpp"
#include "mapper.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/esdf/distance_queries.hpp"
#include "semfuse/esdf/map_changes.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"

namespace semfuse::server {
namespace {

using namespace std::chrono_literals;
constexpr double kVoxel = 0.05;

MapperOptions esdfRoomOptions() {
  MapperOptions options;
  options.volume.voxel_size = kVoxel;
  options.volume.truncation = 2 * kVoxel;
  options.volume.integrate_color = false;
  options.volume.label_rule = volume::LabelRule::kEvidence;
  options.legend = *builtinLegend("synthetic");
  options.observe_free_space = true;
  return options;
}

// The room seen along a 24-frame orbit with ground-truth labels, and its field.
struct Room {
  Mapper mapper{esdfRoomOptions()};
  std::unique_ptr<DistanceField> field;
  Room() {
    esdf::EsdfParams params;
    params.max_distance = 1.0;
    field = std::make_unique<DistanceField>(mapper, params);
    mapper.setChangeListener([this] { field->notify(); });
    field->start();
    synthetic::SequenceConfig config;
    config.intrinsics = config.intrinsics.scaled(0.5);
    config.trajectory.frame_count = 24;
    synthetic::SyntheticSequence sequence(config);
    for (int i = 0; i < config.trajectory.frame_count; ++i) {
      auto both = sequence.frameWithGroundTruth(i);
      EXPECT_TRUE(both.ok());
      auto outcome = mapper.integrateFrame(both.value().first, &both.value().second);
      EXPECT_TRUE(outcome.ok() && outcome.value().integrated);
    }
    EXPECT_TRUE(field->waitUntilCurrent(30s));
  }
};

Room& room() {
  static Room instance;
  return instance;
}

DistanceQueryContext context(const DistanceField* field = &*room().field) {
  DistanceQueryContext c;
  c.field = field;
  c.legend = &room().mapper.legend();
  c.limits.max_points = 4;
  c.max_slice_cells = 200 * 200;
  return c;
}

// The band 0.15-0.6 m over the room's floor plan, the walls included.
OccupancySliceRequest roomBand() {
  OccupancySliceRequest request;
  request.z_min = 0.15;
  request.z_max = 0.6;
  request.use_bounds = true;
  request.min = {-2.5, -2.0};
  request.max = {2.5, 2.0};
  return request;
}

// The cell of a grid under world (x, y).
int8_t cellAt(const OccupancyGrid& grid, double x, double y) {
  const auto column = static_cast<std::size_t>(std::floor((x - grid.origin.x()) / grid.resolution));
  const auto row = static_cast<std::size_t>(std::floor((y - grid.origin.y()) / grid.resolution));
  return grid.cells[row * grid.width + column];
}

TEST(DistanceHandlers, DistanceAndGradientAboveTheTable) {
  auto reply = handleDistance({{{0.0, 0.3, 1.0}, {0.0, 0.0, 9.0}}}, context());
  ASSERT_TRUE(reply.ok()) << reply.message;
  ASSERT_EQ(reply.value.size(), 2u);
  EXPECT_TRUE(reply.value[0].known);
  EXPECT_NEAR(reply.value[0].distance, 0.25, 1.5 * kVoxel);
  EXPECT_GT(reply.value[0].gradient.z(), 0.8f);
  EXPECT_FALSE(reply.value[1].known);  // above the ceiling: nobody saw it
}

TEST(DistanceHandlers, OccupancySliceOfTheRoom) {
  OccupancySliceRequest request = roomBand();
  request.inflation_radius = 0.1;
  auto reply = handleOccupancySlice(request, context());
  ASSERT_TRUE(reply.ok()) << reply.message;
  const OccupancyGrid& grid = reply.value;
  EXPECT_EQ(grid.width, 101u);
  EXPECT_EQ(grid.height, 81u);
  EXPECT_EQ(grid.frame_id, "map");
  EXPECT_DOUBLE_EQ(grid.z, 0.375);
  EXPECT_EQ(cellAt(grid, -2.5, 0.0), kOccupancyOccupied);   // the -x wall
  EXPECT_EQ(cellAt(grid, 1.4, -1.45), kOccupancyOccupied);  // a box
  EXPECT_EQ(cellAt(grid, -1.6, -0.6), kOccupancyFree);
}

TEST(DistanceHandlers, SemanticDistanceToTheTableByLabel) {
  auto reply = handleSemanticDistance({{4}, {{0.2, 0.1, 1.25}}}, context());  // label 4 = table
  ASSERT_TRUE(reply.ok()) << reply.message;
  ASSERT_TRUE(reply.value[0].found);
  EXPECT_EQ(reply.value[0].label, 4);
  EXPECT_NEAR(reply.value[0].distance, 0.5, 1.5 * kVoxel);
  EXPECT_LT(reply.value[0].direction.z(), -0.9f);
  auto slice = handleSemanticSlice({{4}, 1.25, {-1.0, -1.0}, {1.0, 1.0}, 0.1}, context());
  ASSERT_TRUE(slice.ok()) << slice.message;
  EXPECT_EQ(slice.value.distance.size(), cv::Size(20, 20));
  EXPECT_NEAR(slice.value.distance.at<float>(11, 12), 0.5, 1.5 * kVoxel);  // centre (0.25, 0.15)
}

TEST(DistanceHandlers, SegmentCheckThroughTheTableTop) {
  auto reply = handleSegmentCheck({{{{0.2, -0.6, 1.0}, {0.2, 0.8, 0.5}}, {{-1.6, -1.0, 1.0}, {-1.6, 0.5, 1.0}}}, 0.0},
                                  context());
  ASSERT_TRUE(reply.ok()) << reply.message;
  EXPECT_EQ(reply.value[0].status, SegmentStatus::kCollision);
  EXPECT_EQ(reply.value[1].status, SegmentStatus::kFree);
}

TEST(DistanceHandlers, BadRequestsAreRefusedWithAReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto expectRefused = [](const auto& reply, ReplyCode code, const std::string& words) {
    EXPECT_EQ(reply.code, code) << reply.message;
    EXPECT_NE(reply.message.find(words), std::string::npos) << reply.message;
  };
  expectRefused(handleDistance({{{0, nan, 0}}}, context()), ReplyCode::kInvalidArgument, "point 0 is not finite");
  expectRefused(handleDistance({}, context()), ReplyCode::kInvalidArgument, "no points");
  expectRefused(handleDistance({std::vector<Eigen::Vector3d>(5, Eigen::Vector3d::Zero())}, context()),
                ReplyCode::kTooLarge, "5 points exceed the limit of 4");
  OccupancySliceRequest inverted;
  inverted.z_min = 1.0;
  inverted.z_max = 0.5;
  expectRefused(handleOccupancySlice(inverted, context()), ReplyCode::kInvalidArgument, "inverted");
  OccupancySliceRequest flat;
  flat.use_bounds = true;
  flat.min = {0, 0};
  flat.max = {1, 0};
  expectRefused(handleOccupancySlice(flat, context()), ReplyCode::kInvalidArgument, "no area");
  OccupancySliceRequest huge;
  huge.use_bounds = true;
  huge.min = {-50, -50};
  huge.max = {50, 50};
  expectRefused(handleOccupancySlice(huge, context()), ReplyCode::kTooLarge, "--esdf.max-slice-cells");
  expectRefused(handleSemanticDistance({{}, {{0, 0, 1}}}, context()), ReplyCode::kInvalidArgument, "no labels");
  expectRefused(handleSemanticDistance({{900}, {{0, 0, 1}}}, context()), ReplyCode::kInvalidArgument,
                "label 900 is not in the legend");
  expectRefused(handleSemanticSlice({{4}, 1.0, {0, 0}, {0, 1}, 0.1}, context()), ReplyCode::kInvalidArgument,
                "no area");
  expectRefused(handleSemanticSlice({{4}, 1.0, {0, 0}, {1, 1}, 0.0}, context()), ReplyCode::kInvalidArgument,
                "resolution");
  expectRefused(handleSegmentCheck({{{{0, 0, 0}, {0, 0, nan}}}, 0.0}, context()), ReplyCode::kInvalidArgument,
                "segment 0 is not finite");
  expectRefused(handleSegmentCheck({{{{0, 0, 0}, {1, 0, 0}}}, -1.0}, context()), ReplyCode::kInvalidArgument, "radius");
  // Without a field, every service says how to get one.
  expectRefused(handleDistance({{{0, 0, 1}}}, context(nullptr)), ReplyCode::kUnavailable, "--esdf");
  expectRefused(handleOccupancySlice({}, context(nullptr)), ReplyCode::kUnavailable, "--esdf");
}

// The server's field applies a large update in slices of leaves, releasing its lock between them
// (distance_field.cpp); once the last slice is in it holds what one apply of all the changes gives.
TEST(DistanceHandlers, AnUpdateAppliedInSlicesEndsAsOneApply) {
  Room& r = room();
  esdf::EsdfParams params;
  params.max_distance = 1.0;
  esdf::EsdfMap whole(kVoxel, params);
  std::size_t changed_leaves = 0;
  r.mapper.read([&](const volume::LabeledVolume& map) {
    esdf::MapChanges changes = esdf::copyChanges(map, 0);
    changed_leaves = changes.leaves.size();
    whole.apply(changes);
    return 0;
  });
  ASSERT_GT(changed_leaves, 256u) << "the room must need several slices";
  DistanceField sliced(r.mapper, params);  // its first update takes every leaf, in slices
  sliced.start();
  ASSERT_TRUE(sliced.waitUntilCurrent(30s));
  std::vector<Eigen::Vector3d> points;
  for (double x = -1.5; x <= 1.5; x += 0.13)
    for (double y = 0.05; y <= 2.0; y += 0.17)
      for (double z = -1.5; z <= 1.5; z += 0.19) points.emplace_back(x, y, z);
  const std::vector<esdf::DistanceSample> expected = esdf::distancesAt(whole, points);
  std::vector<esdf::DistanceSample> got;
  sliced.read([&](const esdf::EsdfMap& field) { got = esdf::distancesAt(field, points); });
  ASSERT_EQ(got.size(), expected.size());
  std::size_t known = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(got[i].known, expected[i].known) << "point " << i;
    if (!expected[i].known) continue;
    ++known;
    EXPECT_NEAR(got[i].distance, expected[i].distance, 0.25 * kVoxel) << "point " << i;
  }
  EXPECT_GT(known, points.size() / 10);
}

// --esdf.voxel-size: a field of twice the map's voxel, fed by the same map, answers in metres at
// its own resolution (the slice's cells are its voxels).
TEST(DistanceHandlers, AFieldCoarserThanTheMapAnswersAtItsOwnVoxels) {
  constexpr double kCoarse = 2 * kVoxel;
  esdf::EsdfParams params;
  params.max_distance = 1.0;
  params.voxel_size = kCoarse;
  DistanceField coarse(room().mapper, params);
  coarse.start();
  ASSERT_TRUE(coarse.waitUntilCurrent(30s));
  coarse.read([](const esdf::EsdfMap& field) { EXPECT_DOUBLE_EQ(field.voxelSize(), kCoarse); });
  auto distance = handleDistance({{{0.0, 0.3, 1.0}}}, context(&coarse));
  ASSERT_TRUE(distance.ok()) << distance.message;
  EXPECT_TRUE(distance.value[0].known);
  EXPECT_NEAR(distance.value[0].distance, 0.25, 1.5 * kCoarse);
  auto slice = handleOccupancySlice(roomBand(), context(&coarse));
  ASSERT_TRUE(slice.ok()) << slice.message;
  EXPECT_EQ(slice.value.width, 51u);
  EXPECT_EQ(slice.value.height, 41u);
  EXPECT_NEAR(slice.value.resolution, kCoarse, 1e-9);
  EXPECT_EQ(cellAt(slice.value, -2.5, 0.0), kOccupancyOccupied);  // the -x wall
  EXPECT_EQ(cellAt(slice.value, -1.6, -0.6), kOccupancyFree);
  coarse.stop();
}

TEST(DistanceHandlers, TheFieldFollowsAResetAndALoad) {
  Room& r = room();
  const auto saved =
      std::filesystem::temp_directory_path() / ("semfuse_distance_" + std::to_string(::getpid()) + ".vdb");
  ASSERT_TRUE(r.mapper.save(saved).ok());
  r.mapper.reset();
  ASSERT_TRUE(r.field->waitUntilCurrent(30s));
  EXPECT_EQ(r.field->stats().known_voxels, 0u);
  EXPECT_FALSE(handleDistance({{{0.0, 0.3, 1.0}}}, context()).value[0].known);
  ASSERT_TRUE(r.mapper.load(saved).ok());
  std::filesystem::remove(saved);
  ASSERT_TRUE(r.field->waitUntilCurrent(30s));
  auto again = handleDistance({{{0.0, 0.3, 1.0}}}, context());
  ASSERT_TRUE(again.value[0].known);  // free space came back with the file
  EXPECT_NEAR(again.value[0].distance, 0.25, 1.5 * kVoxel);
}

}  // namespace
}  // namespace semfuse::server
