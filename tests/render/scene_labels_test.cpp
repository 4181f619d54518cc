// Labels of the synthetic room fused from exact ground truth: surface voxels carry the label of
// the nearest analytic surface.
#include <gtest/gtest.h>

#include "fused_scene.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"

namespace semfuse::render {
namespace {

TEST(SceneLabels, FusedGroundTruthLabelsAreCorrectOnTheSurface) {
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);
  const synthetic::SyntheticSequence sequence(config);
  volume::VolumeParams p;
  p.voxel_size = 0.02;
  p.truncation = 0.06;
  volume::LabeledVolume volume(p);
  for (int i = 0; i < sequence.frameCount(); i += 15) {
    auto frame = sequence.frameWithGroundTruth(i);
    ASSERT_TRUE(frame.ok()) << frame.error();
    ASSERT_TRUE(volume::integrate(volume, frame.value().first, &frame.value().second).ok());
  }
  // Surface voxels: observed, within half a voxel of the zero crossing, where the truth's own
  // nearest surface is also that close (so a voxel between two objects is not judged).
  size_t surface = 0, correct = 0;
  const double half_voxel = 0.5 * p.voxel_size;
  for (auto it = volume.geometryGrid().cbeginValueOn(); it; ++it) {
    const volume::VoxelValue voxel = volume::unpackVoxel(*it);
    if (std::abs(voxel.tsdf) > half_voxel) continue;
    const auto truth = sequence.scene().nearestSurface(volume.indexToWorld(it.getCoord()));
    if (std::abs(truth.signed_distance) > p.voxel_size) continue;
    ++surface;
    correct += voxel.label == truth.label ? 1 : 0;
  }
  ASSERT_GT(surface, 20000u);
  const double accuracy = static_cast<double>(correct) / surface;
  EXPECT_GE(accuracy, 0.99) << correct << " of " << surface;
  RecordProperty("label_accuracy", std::to_string(accuracy));
}

}  // namespace
}  // namespace semfuse::render
