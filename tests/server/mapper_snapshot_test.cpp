// Mapper::snapshot: the read-only copies of the map that queries run on. A copy a query holds
// never changes under it; a copy nobody holds any more is brought up to date with the changed
// leaves and handed out again; every snapshot equals the map as of the latest write.
#include <gtest/gtest.h>

#include "mapper.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"

namespace semfuse::server {
namespace {

MapperOptions roomOptions() {
  MapperOptions options;
  options.volume.voxel_size = 0.05;
  options.volume.truncation = 0.1;
  options.volume.label_rule = volume::LabelRule::kEvidence;
  options.legend = *builtinLegend("synthetic");
  return options;
}

// Same revision, same observed voxels and the same TSDF values as the map.
void expectEqualsMap(const volume::LabeledVolume& copy, const Mapper& mapper) {
  mapper.read([&](const volume::LabeledVolume& map) {
    EXPECT_EQ(copy.revision(), map.revision());
    EXPECT_EQ(copy.framesIntegrated(), map.framesIntegrated());
    EXPECT_EQ(copy.observedVoxels(), map.observedVoxels());
    std::size_t differ = 0;
    for (auto it = map.geometryGrid().tree().cbeginValueOn(); it; ++it)
      differ += copy.packedVoxel(it.getCoord()) != *it;
    EXPECT_EQ(differ, 0u);
    return 0;
  });
}

TEST(MapperSnapshot, AHeldCopyNeverChangesAndAnIdleOneCatchesUp) {
  Mapper mapper(roomOptions());
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);
  config.trajectory.frame_count = 12;
  synthetic::SyntheticSequence sequence(config);
  const auto integrate = [&](int i) {
    auto both = sequence.frameWithGroundTruth(i);
    ASSERT_TRUE(both.ok()) << both.error();
    auto outcome = mapper.integrateFrame(both.value().first, &both.value().second);
    ASSERT_TRUE(outcome.ok() && outcome.value().integrated);
  };

  EXPECT_EQ(mapper.snapshotBytes(), 0u);  // no query yet: no copy
  integrate(0);
  auto first = mapper.snapshot();
  expectEqualsMap(*first, mapper);
  EXPECT_EQ(mapper.snapshotBytes(), first->memoryBytes());
  EXPECT_EQ(mapper.snapshot(), first);  // no write since: the same copy
  const uint64_t first_revision = first->revision();
  const std::size_t first_voxels = first->observedVoxels();

  integrate(4);
  auto second = mapper.snapshot();  // `first` is held: a new copy
  EXPECT_NE(second, first);
  expectEqualsMap(*second, mapper);
  EXPECT_EQ(first->revision(), first_revision);
  EXPECT_EQ(first->observedVoxels(), first_voxels);
  EXPECT_GT(second->observedVoxels(), first_voxels);
  // Two copies kept, as the status reports them.
  EXPECT_EQ(mapper.snapshotBytes(), first->memoryBytes() + second->memoryBytes());

  // The query that held the first copy ends: the next snapshot is that copy, caught up.
  const volume::LabeledVolume* released = first.get();
  first.reset();
  const uint64_t second_revision = second->revision();
  const std::size_t second_voxels = second->observedVoxels();
  integrate(8);
  auto third = mapper.snapshot();
  EXPECT_EQ(third.get(), released);
  expectEqualsMap(*third, mapper);
  // The second copy, still held, is still as it was.
  EXPECT_EQ(second->revision(), second_revision);
  EXPECT_EQ(second->observedVoxels(), second_voxels);
  EXPECT_GT(third->observedVoxels(), second_voxels);
}

}  // namespace
}  // namespace semfuse::server
