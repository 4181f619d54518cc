// The object experiment of semfuse-eval on the synthetic room: the map's objects, grouped from a
// growing map and queried every few frames, against the room's exact instances (each solid knows
// its object: the table's top and legs are one table, each chair's seat, back and legs one chair).
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>

#include "object_experiment.hpp"
#include "semfuse/synthetic/room.hpp"

namespace semfuse::eval {
namespace {
namespace fs = std::filesystem;

class RoomObjects : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    cache_ = new fs::path(fs::temp_directory_path() / ("semfuse_object_test_" + std::to_string(::getpid())));
    SyntheticOptions options;
    options.frames = 160;
    options.scale = 0.5;
    auto sequence = loadSynthetic(options, *cache_);
    ASSERT_TRUE(sequence.ok()) << sequence.error();
    sequence_ = new EvalSequence(std::move(sequence).value());
  }
  static void TearDownTestSuite() {
    delete sequence_;
    fs::remove_all(*cache_);
    delete cache_;
  }
  static ObjectRunResult run(const ObjectSource& source) {
    ObjectExperimentOptions options;
    options.volume.voxel_size = 0.02;
    options.volume.truncation = 0.08;
    options.volume.integrate_color = false;
    options.query_every = 10;
    auto result = runObjectSource(*sequence_, source, options);
    EXPECT_TRUE(result.ok()) << result.error();
    return result.ok() ? std::move(result).value() : ObjectRunResult{};
  }
  static double idStability(const ObjectRunResult& r) {
    return r.compared_ids ? double(r.kept_ids) / double(r.compared_ids) : 0.0;
  }

  static fs::path* cache_;
  static EvalSequence* sequence_;
};
fs::path* RoomObjects::cache_ = nullptr;
EvalSequence* RoomObjects::sequence_ = nullptr;

TEST_F(RoomObjects, GroundTruthLabelsGiveEveryInstanceWholeWithStableIds) {
  const ObjectRunResult r = run({"ground truth", 0.0, false});
  const ClassCounts& all = r.final_score.total;
  // floor, walls, table, 2 chairs, 3 boxes, 2 spheres, cabinet: those the cameras saw enough of.
  EXPECT_GE(all.true_objects, 9u);
  EXPECT_GE(all.precision(), 0.95) << all.matched << " of " << all.found_objects << " objects match an instance";
  EXPECT_GE(all.recall(), 0.95) << all.matched << " of " << all.true_objects << " instances found";
  // The table (top and four legs) and each chair (seat, back, legs) are one object each.
  const LabelId table = synthetic::labels::kTable, chair = synthetic::labels::kChair;
  ASSERT_TRUE(r.final_score.classes.count(table) && r.final_score.classes.count(chair));
  EXPECT_EQ(r.final_score.classes.at(table).found_objects, 1u);
  EXPECT_EQ(r.final_score.classes.at(table).matched, 1u);
  EXPECT_EQ(r.final_score.classes.at(chair).matched, r.final_score.classes.at(chair).true_objects);
  EXPECT_GE(r.queries, 16u);
  EXPECT_GT(r.compared_ids, 50u);
  EXPECT_GE(idStability(r), 0.99) << r.kept_ids << " of " << r.compared_ids;
}

TEST_F(RoomObjects, ThirtyPercentPixelNoiseStillFindsTheInstances) {
  const ObjectRunResult r = run({"30% pixel noise", 0.3, false});
  const ClassCounts& all = r.final_score.total;
  EXPECT_GE(all.precision(), 0.9) << all.matched << " of " << all.found_objects;
  EXPECT_GE(all.recall(), 0.9) << all.matched << " of " << all.true_objects;
  EXPECT_GE(idStability(r), 0.99) << r.kept_ids << " of " << r.compared_ids;
}

TEST_F(RoomObjects, PanopticInstancesAreUsedWhenTheSegmenterGivesThem) {
  const ObjectRunResult r = run({"panoptic ground truth", 0.0, true});
  const ClassCounts& all = r.final_score.total;
  EXPECT_GE(all.precision(), 0.9) << all.matched << " of " << all.found_objects;
  EXPECT_GE(all.recall(), 0.95) << all.matched << " of " << all.true_objects;
  EXPECT_GE(idStability(r), 0.99) << r.kept_ids << " of " << r.compared_ids;
}

}  // namespace
}  // namespace semfuse::eval
