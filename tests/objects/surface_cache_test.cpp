// The surface cache against a whole extraction: the synthetic room fused frame by frame, the cache
// updated after each stretch of frames re-scans only the leaves the stretch wrote (and their face
// neighbours) and gives extractSurface()'s surface voxel for voxel, in the same order.
#include <gtest/gtest.h>

#include <cstring>

#include "semfuse/objects/surface_cache.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::objects {
namespace {

class SurfaceCacheTest : public ::testing::Test {
 protected:
  SurfaceCacheTest() {
    config_.intrinsics = config_.intrinsics.scaled(0.25);
    config_.trajectory.frame_count = 60;
    sequence_ = std::make_unique<synthetic::SyntheticSequence>(config_);
    volume::VolumeParams params;
    params.voxel_size = 0.04;
    params.truncation = 0.16;
    params.integrate_color = false;
    auto created = volume::LabeledVolume::create(params);
    EXPECT_TRUE(created.ok()) << created.error();
    map_ = std::make_unique<volume::LabeledVolume>(std::move(created).value());
  }

  void integrate(int first, int last) {
    for (int i = first; i < last; ++i) {
      auto both = sequence_->frameWithGroundTruth(i);
      ASSERT_TRUE(both.ok()) << both.error();
      const auto& [frame, labels] = both.value();
      auto stats = volume::integrate(*map_, frame.depth, cv::Mat(), labels.labels, labels.confidence, frame.intrinsics,
                                     sequence_->pose(i));
      ASSERT_TRUE(stats.ok()) << stats.error();
    }
  }

  static void expectSameSurface(const SurfaceVoxels& cached, const SurfaceVoxels& whole) {
    ASSERT_EQ(cached.size(), whole.size());
    for (std::size_t i = 0; i < whole.size(); ++i) {
      ASSERT_EQ(cached[i].ijk, whole[i].ijk) << "voxel " << i;
      ASSERT_EQ(cached[i].label, whole[i].label) << "voxel " << i;
      ASSERT_EQ(std::memcmp(&cached[i].normal, &whole[i].normal, sizeof whole[i].normal), 0) << "voxel " << i;
      ASSERT_EQ(cached[i].area_m2, whole[i].area_m2) << "voxel " << i;
      ASSERT_EQ(cached[i].score, whole[i].score) << "voxel " << i;
    }
  }

  const LabelLegend legend_ = *builtinLegend("synthetic");
  synthetic::SequenceConfig config_;
  std::unique_ptr<synthetic::SyntheticSequence> sequence_;
  std::unique_ptr<volume::LabeledVolume> map_;
};

TEST_F(SurfaceCacheTest, RescansOnlyWhatChangedAndGivesTheWholeExtraction) {
  SurfaceCache cache(legend_);
  integrate(0, 30);
  const SurfaceVoxels first = cache.update(*map_);
  EXPECT_EQ(cache.lastScannedLeaves(), map_->allocatedLeaves());
  EXPECT_GT(first.size(), 1000u);
  expectSameSurface(first, extractSurface(*map_, legend_));

  // Nothing written: nothing scanned, the same surface.
  expectSameSurface(cache.update(*map_), first);
  EXPECT_EQ(cache.lastScannedLeaves(), 0u);

  // Three more frames write part of the map: those leaves and their neighbours are scanned.
  const uint64_t before = map_->revision();
  integrate(30, 33);
  const std::size_t changed = map_->changesSince(before).leaves.size();
  ASSERT_GT(changed, 0u);
  const SurfaceVoxels later = cache.update(*map_);
  EXPECT_GE(cache.lastScannedLeaves(), changed);
  EXPECT_LT(cache.lastScannedLeaves(), map_->allocatedLeaves());
  expectSameSurface(later, extractSurface(*map_, legend_));

  // A cleared map is scanned whole.
  map_->clear();
  integrate(40, 42);
  const SurfaceVoxels after_clear = cache.update(*map_);
  EXPECT_EQ(cache.lastScannedLeaves(), map_->allocatedLeaves());
  expectSameSurface(after_clear, extractSurface(*map_, legend_));
}

}  // namespace
}  // namespace semfuse::objects
