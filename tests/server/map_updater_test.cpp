// The live mesh without DDS: the block store (what changes, pages, tombstones), the updater's
// rounds on a map that grows, is cleared and is replaced, the parts of a large update, the idle
// updater that catches up, and a follower that applies what it was sent ending with the server's
// mesh. The map is the synthetic room fused from a few small views.
#include <limits>
#include <map>
#include <shared_mutex>
#include <vector>

#include <gtest/gtest.h>

#include "eventually.hpp"
#include "map_blocks_handler.hpp"
#include "map_updater.hpp"
#include "mesh_block_encoding.hpp"
#include "mesh_block_store.hpp"
#include "semfuse/render/mesh_blocks.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/synthetic/trajectory.hpp"
#include "semfuse/synthetic/view_renderer.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::server {
namespace {

const PinholeIntrinsics kCamera{160, 120, 131.25, 131.25, 79.5, 59.5};

// A volume behind a shared mutex, as the server's Mapper keeps it.
class LockedVolume final : public MapAccess {
 public:
  LockedVolume() : volume_(params()) {}
  static volume::VolumeParams params() {
    volume::VolumeParams p;
    p.voxel_size = 0.02;
    p.truncation = 0.08;
    p.label_rule = volume::LabelRule::kEvidence;
    return p;
  }
  void read(const std::function<void(const volume::LabeledVolume&)>& fn) const override {
    std::shared_lock lock(mutex_);
    fn(volume_);
  }
  std::shared_ptr<const volume::LabeledVolume> snapshot() const override {
    std::shared_lock lock(mutex_);
    return std::make_shared<const volume::LabeledVolume>(volume_.deepCopy());
  }
  const LabelLegend& legend() const override { return legend_; }

  // Fuses the room as seen from `eye`, looking at the table.
  void see(const Eigen::Vector3d& eye) {
    static const synthetic::LabeledScene room = synthetic::makeRoom();
    const Pose pose = synthetic::lookAt(eye, {0.2, 0.1, 0.7});
    const auto view = synthetic::renderView(room, kCamera, pose);
    ASSERT_TRUE(view.ok()) << view.error();
    std::unique_lock lock(mutex_);
    const auto& v = view.value();
    ASSERT_TRUE(volume::integrate(volume_, v.depth, v.color, v.labels, cv::Mat(), kCamera, pose).ok());
  }
  void clear() {
    std::unique_lock lock(mutex_);
    volume_.clear();
  }
  template <class Fn>
  void write(Fn&& fn) {
    std::unique_lock lock(mutex_);
    fn(volume_);
  }

 private:
  mutable std::shared_mutex mutex_;
  volume::LabeledVolume volume_;
  LabelLegend legend_;
};

class RecordingSink final : public MapUpdater::Sink {
 public:
  bool listening() const override { return listening_; }
  void publish(const MapUpdate& update) override { updates.push_back(update); }
  bool listening_ = true;
  std::vector<MapUpdate> updates;
};

// What a viewer keeps: the newest mesh of every block, forgetting those older than a clear.
class Follower {
 public:
  void apply(const MapUpdate& update) {
    if (update.header.cleared_revision > cleared_) {
      cleared_ = update.header.cleared_revision;
      for (auto it = blocks_.begin(); it != blocks_.end();)
        it = it->second.revision < cleared_ ? blocks_.erase(it) : std::next(it);
    }
    for (const MeshBlock& block : update.blocks) {
      auto& kept = blocks_[block.origin];
      if (block.revision >= kept.revision) kept = block;
    }
  }
  // Blocks with surface and their vertex counts.
  std::map<BlockOrigin, std::size_t> vertexCounts() const {
    std::map<BlockOrigin, std::size_t> counts;
    for (const auto& [origin, block] : blocks_)
      if (!block.empty()) counts[origin] = block.vertexCount();
    return counts;
  }

 private:
  uint64_t cleared_ = 0;
  std::map<BlockOrigin, MeshBlock> blocks_;
};

std::map<BlockOrigin, std::size_t> storeCounts(const MeshBlockStore& store) {
  std::map<BlockOrigin, std::size_t> counts;
  store.visitBlocks([&](const std::vector<const MeshBlock*>& blocks) {
    for (const MeshBlock* b : blocks) counts[b->origin] = b->vertexCount();
  });
  return counts;
}

// Every block of the map meshed from scratch, on the lattice of `stride` map voxels.
std::map<BlockOrigin, std::size_t> freshCounts(const LockedVolume& map, int stride = 1) {
  std::map<BlockOrigin, std::size_t> counts;
  map.read([&](const volume::LabeledVolume& volume) {
    std::vector<openvdb::Coord> leaves;
    for (auto leaf = volume.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf) leaves.push_back(leaf->origin());
    for (const auto& mesh : render::extractBlockMeshes(volume, render::blocksReadingLeaves(leaves, stride), stride))
      if (!mesh.mesh.vertices.empty())
        counts[{mesh.origin.x(), mesh.origin.y(), mesh.origin.z()}] = mesh.mesh.vertices.size();
  });
  return counts;
}

MeshBlock block(BlockOrigin origin, uint64_t revision, std::size_t vertices) {
  MeshBlock b;
  b.origin = origin;
  b.revision = revision;
  b.own_vertices = static_cast<uint32_t>(vertices);
  b.positions.assign(3 * vertices, 100);
  b.normals.assign(3 * vertices, 0);
  b.labels.assign(vertices, 2);
  b.scores.assign(vertices, 1.0F);
  return b;
}

TEST(MeshBlockStore, KeepsWhatChangedAndSaysSo) {
  MeshBlockStore store(42);
  EXPECT_EQ(store.header().session, 42u);
  auto changed = store.apply({block({0, 0, 0}, 5, 10), block({8, 0, 0}, 5, 4), block({16, 0, 0}, 5, 0)});
  ASSERT_EQ(changed.size(), 2u);  // an empty block nobody has is not news
  // The same meshes again change nothing and keep their revision; a new mesh replaces the old.
  changed = store.apply({block({0, 0, 0}, 9, 10), block({8, 0, 0}, 9, 6)});
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].origin, (BlockOrigin{8, 0, 0}));
  // A block whose surface went away is sent empty and kept as such.
  changed = store.apply({block({0, 0, 0}, 12, 0)});
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_TRUE(changed[0].empty());
  store.setCurrent(12, 3, 0.02);
  EXPECT_EQ(store.totals().blocks, 1u);
  EXPECT_EQ(store.totals().vertices, 6u);

  // A new follower gets the block with surface only; one that has revision 6 hears of the removal
  // and the new mesh; one that has 12 gets nothing.
  auto page = store.page({0, std::nullopt, 0}, 1 << 20);
  ASSERT_EQ(page.blocks.size(), 1u);
  EXPECT_EQ(page.blocks[0].revision, 9u);
  EXPECT_TRUE(page.complete);
  EXPECT_EQ(page.header.revision, 12u);
  page = store.page({6, std::nullopt, 0}, 1 << 20);
  ASSERT_EQ(page.blocks.size(), 2u);
  EXPECT_TRUE(page.blocks[0].empty());
  EXPECT_TRUE(store.page({12, std::nullopt, 0}, 1 << 20).blocks.empty());

  // A clear forgets everything.
  store.clear(20);
  EXPECT_EQ(store.header().cleared_revision, 20u);
  EXPECT_EQ(store.totals().blocks, 0u);
  EXPECT_TRUE(store.page({6, std::nullopt, 0}, 1 << 20).blocks.empty());
}

TEST(MeshBlockStore, PagesCoverEveryBlockOnceWithinTheirBound) {
  MeshBlockStore store(1);
  std::vector<MeshBlock> blocks;
  for (int i = 0; i < 50; ++i) blocks.push_back(block({8 * i, -8, 0}, 3, 20 + i));
  store.apply(blocks);
  std::vector<BlockOrigin> seen;
  MapBlocksRequest request;
  request.max_bytes = 2000;
  for (int pages = 1;; ++pages) {
    ASSERT_LT(pages, 100);
    const MapBlocksPage page = store.page(request, 1 << 20);
    std::size_t bytes = 0;
    for (const MeshBlock& b : page.blocks) {
      seen.push_back(b.origin);
      bytes += b.payloadBytes() + MeshBlock::kFramingBytes;
    }
    ASSERT_FALSE(page.blocks.empty());
    EXPECT_TRUE(bytes <= request.max_bytes || page.blocks.size() == 1) << bytes;
    if (page.complete) break;
    request.resume_after = page.next_after;
  }
  ASSERT_EQ(seen.size(), 50u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(seen[static_cast<std::size_t>(i)], (BlockOrigin{8 * i, -8, 0}));
}

// Positions in 1/4096 voxel and normals in 1/127, rounded to nearest with halves away from zero,
// clamped to what the wire types hold.
TEST(MeshBlockEncoding, RoundsToTheNearestUnitAndClamps) {
  render::BlockMesh mesh;
  mesh.origin = openvdb::Coord(8, -16, 24);
  mesh.own_vertices = 2;
  const float half_unit = 0.5F / MeshBlock::kPositionScale;
  mesh.mesh.vertices = {{half_unit, 3.0F * half_unit, 9.0F}, {-0.25F, 0.49F / MeshBlock::kPositionScale, 20.0F}};
  mesh.mesh.normals = {{0.5F / 127.0F, -0.5F / 127.0F, 1.0F}, {-1.0F, std::numeric_limits<float>::quiet_NaN(), 0.6F}};
  mesh.mesh.labels = {3, 4};
  mesh.mesh.scores = {0.5F, 0.25F};
  mesh.mesh.triangles = {{0, 1, 0}};
  const MeshBlock block = encodeMeshBlock(mesh, 7);

  EXPECT_EQ(block.origin, (BlockOrigin{8, -16, 24}));
  EXPECT_EQ(block.revision, 7u);
  EXPECT_EQ(block.own_vertices, 2u);
  // 0.5 and 1.5 units round up; 9 voxels are 36864 units; below 0 and beyond 65535 are clamped.
  EXPECT_EQ(block.positions, (std::vector<uint16_t>{1, 2, 36864, 0, 0, 65535}));
  // 0.6 * 127 = 76.2; a NaN component is 0.
  EXPECT_EQ(block.normals, (std::vector<int8_t>{1, -1, 127, -127, 0, 76}));
  EXPECT_EQ(block.labels, (std::vector<LabelId>{3, 4}));
  EXPECT_EQ(block.triangles, (std::vector<uint16_t>{0, 1, 0}));
  EXPECT_TRUE(block.colors.empty());
}

TEST(MapBlocksHandler, RefusesWhatItCannotServe) {
  EXPECT_EQ(handleMapBlocks({}, nullptr, 1 << 20).code, ReplyCode::kUnavailable);
  MeshBlockStore store(1);
  store.setCurrent(10, 1, 0.02);
  const auto ahead = handleMapBlocks({11, std::nullopt, 0}, &store, 1 << 20);
  EXPECT_EQ(ahead.code, ReplyCode::kInvalidArgument);
  EXPECT_NE(ahead.message.find("ahead of the map's mesh (revision 10)"), std::string::npos) << ahead.message;
  EXPECT_TRUE(handleMapBlocks({10, std::nullopt, 0}, &store, 1 << 20).ok());
}

class MapUpdaterTest : public ::testing::Test {
 protected:
  MapUpdaterTest() : updater_(map_, config(), sink_) {}
  static MapUpdateConfig config() {
    MapUpdateConfig c;
    c.batch_blocks = 64;  // several holds of the lock per round
    return c;
  }
  LockedVolume map_;
  RecordingSink sink_;
  MapUpdater updater_;
};

TEST_F(MapUpdaterTest, RoundsSendWhatChangedAndAFollowerEndsWithTheServersMesh) {
  Follower follower;
  map_.see({-1.5, -1.2, 1.4});
  MapUpdater::Round first = updater_.update();
  ASSERT_EQ(sink_.updates.size(), 1u);
  const MapUpdate& u1 = sink_.updates[0];
  EXPECT_EQ(u1.previous_revision, 0u);
  EXPECT_EQ(u1.header.revision, 1u);
  EXPECT_EQ(u1.header.frames_integrated, 1u);
  EXPECT_EQ(u1.header.voxel_size, 0.02);
  EXPECT_EQ(u1.parts, 1u);
  EXPECT_GT(first.blocks_sent, 100u);
  EXPECT_GT(first.blocks_meshed, first.blocks_sent);  // the seven blocks below each leaf too
  follower.apply(u1);
  EXPECT_EQ(follower.vertexCounts(), freshCounts(map_));

  // Nothing changed: nothing is sent.
  updater_.update();
  EXPECT_EQ(sink_.updates.size(), 1u);

  // A second view from the other side: the update holds the blocks that view changed, fewer
  // than the map has, and the follower is again equal to the map.
  map_.see({1.6, 1.3, 1.5});
  const MapUpdater::Round second = updater_.update();
  ASSERT_EQ(sink_.updates.size(), 2u);
  const MapUpdate& u2 = sink_.updates[1];
  EXPECT_EQ(u2.previous_revision, 1u);
  EXPECT_EQ(u2.header.revision, 2u);
  EXPECT_EQ(second.blocks_sent, u2.blocks.size());
  EXPECT_LT(u2.blocks.size(), updater_.store().totals().blocks);
  for (const MeshBlock& b : u2.blocks) EXPECT_EQ(b.revision, 2u);
  follower.apply(u2);
  EXPECT_EQ(follower.vertexCounts(), freshCounts(map_));
  EXPECT_EQ(storeCounts(updater_.store()), freshCounts(map_));
  const MapUpdater::Totals totals = updater_.totals();
  EXPECT_EQ(totals.updates, 2u);
  EXPECT_EQ(totals.blocks_sent, first.blocks_sent + second.blocks_sent);
}

// A live mesh of twice the map's voxel: the header says its voxel, and a follower ends with the
// blocks of that lattice meshed from scratch, with far fewer vertices than the map's own.
TEST(MapUpdater, ACoarserLiveMeshFollowsTheMapOnItsOwnLattice) {
  LockedVolume map;
  RecordingSink sink;
  MapUpdateConfig config;
  config.voxel_size = 0.04;
  ASSERT_TRUE(validateMapUpdateConfig(config, 0.02, 0.08).ok());
  ASSERT_EQ(config.stride(0.02, 0.08), 2);
  MapUpdater updater(map, config, sink);
  Follower follower;
  map.see({-1.5, -1.2, 1.4});
  updater.update();
  ASSERT_EQ(sink.updates.size(), 1u);
  EXPECT_EQ(sink.updates[0].header.voxel_size, 0.04);
  follower.apply(sink.updates[0]);
  map.see({1.6, 1.3, 1.5});
  updater.update();
  ASSERT_EQ(sink.updates.size(), 2u);
  follower.apply(sink.updates[1]);
  const auto coarse = freshCounts(map, 2), fine = freshCounts(map, 1);
  EXPECT_EQ(follower.vertexCounts(), coarse);
  auto total = [](const std::map<BlockOrigin, std::size_t>& counts) {
    std::size_t n = 0;
    for (const auto& [origin, count] : counts) n += count;
    return n;
  };
  EXPECT_GT(total(coarse), 1000u);
  EXPECT_LT(total(coarse), total(fine) / 3);
}

// By default the live mesh takes the coarsest whole multiple of the map's voxel up to 2 cm and the
// truncation; a given voxel must be such a multiple (1 to 8 times) and within the truncation.
TEST(MapUpdateConfig, TheLiveVoxelIsAWholeMultipleOfTheMapsWithinTheTruncation) {
  const MapUpdateConfig automatic;
  EXPECT_EQ(automatic.stride(0.01, 0.04), 2);
  EXPECT_EQ(automatic.stride(0.005, 0.04), 4);
  EXPECT_EQ(automatic.stride(0.005, 0.015), 3);  // the truncation bounds it
  EXPECT_EQ(automatic.stride(0.02, 0.08), 1);
  EXPECT_EQ(automatic.stride(0.05, 0.2), 1);
  EXPECT_TRUE(validateMapUpdateConfig(automatic, 0.01, 0.04).ok());

  MapUpdateConfig given;
  given.voxel_size = 0.01;
  EXPECT_EQ(given.stride(0.01, 0.04), 1);
  EXPECT_TRUE(validateMapUpdateConfig(given, 0.01, 0.04).ok());
  given.voxel_size = 0.03;
  EXPECT_EQ(given.stride(0.01, 0.04), 3);
  EXPECT_TRUE(validateMapUpdateConfig(given, 0.01, 0.04).ok());
  given.voxel_size = 0.015;
  EXPECT_FALSE(validateMapUpdateConfig(given, 0.01, 0.04).ok());  // not a whole multiple
  given.voxel_size = 0.005;
  EXPECT_FALSE(validateMapUpdateConfig(given, 0.01, 0.04).ok());  // finer than the map
  given.voxel_size = 0.05;
  const Status wide = validateMapUpdateConfig(given, 0.01, 0.04);
  ASSERT_FALSE(wide.ok());
  EXPECT_NE(wide.error().find("truncation"), std::string::npos) << wide.error();
  given.voxel_size = 0.09;
  EXPECT_FALSE(validateMapUpdateConfig(given, 0.01, 0.1).ok());  // more than 8 times
}

TEST_F(MapUpdaterTest, AClearIsSentAndTheNewMapFollows) {
  Follower follower;
  map_.see({-1.5, -1.2, 1.4});
  updater_.update();
  follower.apply(sink_.updates.back());
  map_.clear();
  updater_.update();
  ASSERT_EQ(sink_.updates.size(), 2u);
  const MapUpdate& cleared = sink_.updates.back();
  EXPECT_TRUE(cleared.blocks.empty());
  EXPECT_EQ(cleared.header.cleared_revision, cleared.header.revision);
  follower.apply(cleared);
  EXPECT_TRUE(follower.vertexCounts().empty());

  map_.see({1.6, 1.3, 1.5});
  updater_.update();
  follower.apply(sink_.updates.back());
  EXPECT_FALSE(follower.vertexCounts().empty());
  EXPECT_EQ(follower.vertexCounts(), freshCounts(map_));
}

TEST_F(MapUpdaterTest, ALoadedMapReplacesEverything) {
  map_.see({-1.5, -1.2, 1.4});
  updater_.update();
  // A map from elsewhere (another view), continuing the revisions as Mapper::load does.
  LockedVolume other;
  other.see({1.6, 1.3, 1.5});
  map_.write([&](volume::LabeledVolume& volume) {
    other.write([&](volume::LabeledVolume& loaded) {
      volume::LabeledVolume replacement = loaded.deepCopy();
      replacement.continueRevisionsFrom(volume.revision());
      volume = std::move(replacement);
    });
  });
  updater_.update();
  const MapUpdate& replaced = sink_.updates.back();
  EXPECT_EQ(replaced.header.cleared_revision, replaced.header.revision);
  Follower follower;
  for (const MapUpdate& u : sink_.updates) follower.apply(u);
  EXPECT_EQ(follower.vertexCounts(), freshCounts(map_));
  EXPECT_EQ(follower.vertexCounts(), freshCounts(other));
}

TEST(MapUpdater, LargeUpdatesComeInPartsOfBoundedSize) {
  LockedVolume map;
  RecordingSink sink;
  MapUpdateConfig config;
  config.sample_bytes = 64 * 1024;
  MapUpdater updater(map, config, sink);
  map.see({-1.5, -1.2, 1.4});
  updater.update();
  ASSERT_GT(sink.updates.size(), 2u);
  Follower follower;
  for (std::size_t i = 0; i < sink.updates.size(); ++i) {
    const MapUpdate& part = sink.updates[i];
    EXPECT_EQ(part.part, i);
    EXPECT_EQ(part.parts, sink.updates.size());
    EXPECT_EQ(part.header.revision, sink.updates[0].header.revision);
    std::size_t bytes = 0;
    for (const MeshBlock& b : part.blocks) bytes += b.payloadBytes() + MeshBlock::kFramingBytes;
    EXPECT_LE(bytes, config.sample_bytes);
    follower.apply(part);
  }
  EXPECT_EQ(follower.vertexCounts(), freshCounts(map));
}

TEST(MapUpdater, WithNobodyListeningItIdlesThenCatchesUp) {
  LockedVolume map;
  RecordingSink sink;
  sink.listening_ = false;
  MapUpdater updater(map, MapUpdateConfig{}, sink);
  map.see({-1.5, -1.2, 1.4});
  EXPECT_TRUE(updater.update().skipped);
  map.see({1.6, 1.3, 1.5});
  EXPECT_TRUE(updater.update().skipped);
  EXPECT_TRUE(sink.updates.empty());
  EXPECT_EQ(updater.store().header().revision, 0u);

  // A map_blocks request wakes it without a reader; the next round catches up with both views.
  updater.touch();
  EXPECT_FALSE(updater.update().skipped);
  ASSERT_FALSE(sink.updates.empty());
  for (const MapUpdate& part : sink.updates) EXPECT_EQ(part.header.revision, 2u);  // one update, maybe in parts
  EXPECT_EQ(storeCounts(updater.store()), freshCounts(map));
  // The page a late follower asks for is the whole mesh.
  const MapBlocksPage page = updater.store().page({}, 1u << 30);
  EXPECT_TRUE(page.complete);
  EXPECT_EQ(page.blocks.size(), freshCounts(map).size());
}

TEST(MapUpdater, TheThreadPublishesAtItsRate) {
  LockedVolume map;
  RecordingSink sink;
  MapUpdateConfig config;
  config.rate_hz = 20.0;
  MapUpdater updater(map, config, sink);
  updater.start();
  map.see({-1.5, -1.2, 1.4});
  // Rounds go on at the rate (counted, not timed: a busy machine delays them); one had the view to send.
  EXPECT_TRUE(semfuse::testing::eventually([&] { return updater.totals().rounds >= 4u; }));
  updater.stop();
  EXPECT_EQ(updater.totals().updates, 1u);
}

}  // namespace
}  // namespace semfuse::server
