// Algorithm 1 (Cavallari & Di Stefano, PSIVT 2015), branch by branch: first the pure update rule,
// then the same branches through integrate()/integrateLabels() on a wall 1 m in front of the camera.
#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/label_fusion.hpp"

namespace semfuse::volume {
namespace {
using testing::smallCamera;

TEST(LabelEvidence, UnlabeledVoxelTakesTheLabelWithThePixelConfidence) {
  LabelId label = kUnlabeled;
  float score = 0;
  fuseLabelEvidence(label, score, 5, 0.7f, 16);
  EXPECT_EQ(label, 5);
  EXPECT_FLOAT_EQ(score, 0.7f);
}

TEST(LabelEvidence, SameLabelAddsUpToTheClamp) {
  LabelId label = 5;
  float score = 2.0f;
  fuseLabelEvidence(label, score, 5, 0.5f, 3.0f);
  EXPECT_FLOAT_EQ(score, 2.5f);
  fuseLabelEvidence(label, score, 5, 0.9f, 3.0f);
  EXPECT_FLOAT_EQ(score, 3.0f);
  EXPECT_EQ(label, 5);
}

TEST(LabelEvidence, OtherLabelSubtractsAndKeepsTheLabel) {
  LabelId label = 5;
  float score = 1.0f;
  fuseLabelEvidence(label, score, 7, 0.75f, 16);
  EXPECT_EQ(label, 5);
  EXPECT_FLOAT_EQ(score, 0.25f);
  fuseLabelEvidence(label, score, 7, 0.75f, 16);  // goes negative: label kept for now
  EXPECT_EQ(label, 5);
  EXPECT_FLOAT_EQ(score, -0.5f);
}

TEST(LabelEvidence, NegativeScoreIsReplacedByTheNextObservation) {
  LabelId label = 5;
  float score = -0.5f;
  fuseLabelEvidence(label, score, 9, 0.4f, 16);
  EXPECT_EQ(label, 9);
  EXPECT_FLOAT_EQ(score, 0.4f);
}

// A camera at the origin looking down +z at a wall 1 m away; the voxel on the wall straight ahead.
// The volumes fuse with Algorithm 1, the evidence rule (the default is bayes).
class LabelFusionInVolume : public ::testing::Test {
 protected:
  static VolumeParams evidenceParams() {
    VolumeParams params;
    params.label_rule = LabelRule::kEvidence;
    return params;
  }

  const PinholeIntrinsics k = smallCamera();
  const Pose pose = Pose::Identity();
  const cv::Mat depth = cv::Mat(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  const openvdb::Coord wall{0, 0, 100};

  static cv::Mat labels(LabelId id, cv::Size size = {160, 120}) { return {size, CV_16UC1, cv::Scalar(id)}; }
  static cv::Mat confidence(float w, cv::Size size = {160, 120}) { return {size, CV_32FC1, cv::Scalar(w)}; }

  void fuse(LabeledVolume& volume, LabelId id, float w) {
    auto r = integrate(volume, depth, cv::Mat(), labels(id), confidence(w), k, pose);
    ASSERT_TRUE(r.ok()) << r.error();
  }
};

TEST_F(LabelFusionInVolume, EveryBranchOfAlgorithmOne) {
  VolumeParams params = evidenceParams();
  params.max_label_score = 2.0f;
  LabeledVolume volume(params);
  fuse(volume, 5, 0.75f);  // unlabeled: take
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, 0.75f);
  fuse(volume, 5, 0.75f);  // same: add
  EXPECT_EQ(volume.voxel(wall).score, 1.5f);
  fuse(volume, 5, 0.75f);  // same: add, clamped at W_clamp = 2
  EXPECT_EQ(volume.voxel(wall).score, 2.0f);
  fuse(volume, 7, 1.0f);  // other: subtract
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, 1.0f);
  fuse(volume, 7, 1.0f);
  fuse(volume, 7, 0.5f);  // score 1 - 1 - 0.5 < 0, label still 5
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, -0.5f);
  fuse(volume, 7, 0.25f);  // negative: replaced
  EXPECT_EQ(volume.voxel(wall).label, 7);
  EXPECT_EQ(volume.voxel(wall).score, 0.25f);
  // Voxels up to the truncation in front of and behind the wall are labeled too, not beyond.
  EXPECT_EQ(volume.voxel({0, 0, 97}).label, 7);
  EXPECT_EQ(volume.voxel({0, 0, 103}).label, 7);
}

TEST_F(LabelFusionInVolume, UnlabeledPixelsChangeNothing) {
  LabeledVolume volume(evidenceParams());
  fuse(volume, 5, 0.75f);
  fuse(volume, kUnlabeled, 1.0f);
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, 0.75f);
}

TEST_F(LabelFusionInVolume, BackgroundLabelsChangeNothing) {
  VolumeParams params = evidenceParams();
  params.background_labels = {3, 11};
  LabeledVolume volume(params);
  fuse(volume, 3, 1.0f);
  EXPECT_EQ(volume.voxel(wall).label, kUnlabeled);  // not even an unlabeled voxel takes it
  EXPECT_TRUE(volume.voxel(wall).observed());
  fuse(volume, 5, 0.5f);
  fuse(volume, 11, 1.0f);
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, 0.5f);
}

TEST_F(LabelFusionInVolume, ZeroOrInvalidConfidenceChangesNothing) {
  LabeledVolume volume(evidenceParams());
  fuse(volume, 5, 0.0f);
  EXPECT_EQ(volume.voxel(wall).label, kUnlabeled);
  fuse(volume, 5, std::numeric_limits<float>::quiet_NaN());
  EXPECT_EQ(volume.voxel(wall).label, kUnlabeled);
}

TEST_F(LabelFusionInVolume, LateSegmentationLabelsWithoutTouchingGeometry) {
  LabeledVolume volume(evidenceParams());
  ASSERT_TRUE(integrate(volume, depth, cv::Mat(), k, pose).ok());
  const VoxelValue before = volume.voxel(wall);
  ASSERT_EQ(before.label, kUnlabeled);
  auto r = integrateLabels(volume, depth, labels(4), confidence(0.5f), k, pose);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_GT(r.value().voxels_labeled, 1000u);
  EXPECT_EQ(r.value().voxels_updated, 0u);
  const VoxelValue after = volume.voxel(wall);
  EXPECT_EQ(after.label, 4);
  EXPECT_EQ(after.score, 0.5f);
  EXPECT_EQ(after.tsdf, before.tsdf);
  EXPECT_EQ(after.weight, before.weight);
  EXPECT_EQ(volume.framesIntegrated(), 1u);
  // Never-observed space stays unobserved: late labels allocate and create nothing.
  const std::size_t leaves = volume.allocatedLeaves();
  const cv::Mat farther(k.height, k.width, CV_32FC1, cv::Scalar(2.0));
  ASSERT_TRUE(integrateLabels(volume, farther, labels(4), confidence(0.5f), k, pose).ok());
  EXPECT_EQ(volume.allocatedLeaves(), leaves);
  EXPECT_FALSE(volume.voxel({0, 0, 200}).observed());
}

TEST_F(LabelFusionInVolume, DepthDisagreementChangesNothing) {
  LabeledVolume volume(evidenceParams());
  fuse(volume, 5, 0.75f);
  // The segmentation's frame saw a surface 10 cm behind the wall voxels: they do not agree.
  const cv::Mat behind(k.height, k.width, CV_32FC1, cv::Scalar(1.1));
  auto r = integrateLabels(volume, behind, labels(8), confidence(1.0f), k, pose);
  ASSERT_TRUE(r.ok()) << r.error();
  EXPECT_EQ(r.value().voxels_labeled, 0u);
  EXPECT_EQ(volume.voxel(wall).label, 5);
  EXPECT_EQ(volume.voxel(wall).score, 0.75f);
}

TEST_F(LabelFusionInVolume, SmallerLabelImagesAreUpsampledNearestNeighbour) {
  LabeledVolume volume(evidenceParams());
  cv::Mat half_labels = labels(1, {80, 60});
  half_labels.colRange(40, 80).setTo(2);  // right half of the image: label 2
  ASSERT_TRUE(integrate(volume, depth, cv::Mat(), half_labels, confidence(1.0f, {80, 60}), k, pose).ok());
  // At 1 m, x = (u - 79.5) / 150: u = 40 -> x = -0.26 m, u = 120 -> x = +0.27 m.
  EXPECT_EQ(volume.voxel({-26, 0, 100}).label, 1);
  EXPECT_EQ(volume.voxel({27, 0, 100}).label, 2);
  // Without confidence every labeled pixel counts 1.
  LabeledVolume unweighted;
  ASSERT_TRUE(integrate(unweighted, depth, cv::Mat(), half_labels, cv::Mat(), k, pose).ok());
  EXPECT_EQ(unweighted.voxel({27, 0, 100}).score, 1.0f);
}

}  // namespace
}  // namespace semfuse::volume
