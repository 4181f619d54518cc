// The label passes of semfuse-eval on a small synthetic sequence: p = 0 reproduces every rule's
// reference exactly, noise makes errors the metric sees, the noise sources behave as documented,
// and the diagnosis (experiment 6) agrees with the metric and its exact-count oracle is sound.
#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>

#include <opencv2/core.hpp>

#include "label_diagnosis.hpp"
#include "label_passes.hpp"

namespace semfuse::eval {
namespace {
namespace fs = std::filesystem;

class SmallSyntheticScenario : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    cache_ = new fs::path(fs::temp_directory_path() / ("semfuse_eval_test_" + std::to_string(::getpid())));
    SyntheticOptions options;
    options.frames = 12;
    options.scale = 0.25;
    auto sequence = loadSynthetic(options, *cache_);
    ASSERT_TRUE(sequence.ok()) << sequence.error();
    sequence_ = new EvalSequence(std::move(sequence).value());
    params_ = new volume::VolumeParams();
    params_->voxel_size = 0.04;
    params_->truncation = 0.16;
    params_->integrate_color = false;
    auto geometry = integrateGeometry(*sequence_, *params_);
    ASSERT_TRUE(geometry.ok()) << geometry.error();
    scenario_ = new Scenario(*sequence_, std::move(geometry).value());
  }
  static void TearDownTestSuite() {
    delete scenario_;
    delete sequence_;
    delete params_;
    fs::remove_all(*cache_);
    delete cache_;
  }
  static volume::VolumeParams rule(volume::LabelRule r) {
    volume::VolumeParams p = *params_;
    p.label_rule = r;
    return p;
  }

  static fs::path* cache_;
  static EvalSequence* sequence_;
  static volume::VolumeParams* params_;
  static Scenario* scenario_;
};
fs::path* SmallSyntheticScenario::cache_ = nullptr;
EvalSequence* SmallSyntheticScenario::sequence_ = nullptr;
volume::VolumeParams* SmallSyntheticScenario::params_ = nullptr;
Scenario* SmallSyntheticScenario::scenario_ = nullptr;

TEST_F(SmallSyntheticScenario, TheRoomShowsItsLabelsAndASurface) {
  EXPECT_GE(sequence_->present_labels.size(), 4u);  // floor, walls, furniture at least
  EXPECT_GT(scenario_->surface().size(), 1000u);
}

TEST_F(SmallSyntheticScenario, ZeroNoiseGivesZeroErrorForEveryRule) {
  for (auto r : {volume::LabelRule::kEvidence, volume::LabelRule::kMajority, volume::LabelRule::kBayes})
    for (auto kind : {LabelSourceKind::kPixel, LabelSourceKind::kRegion}) {
      auto outcome = scenario_->run(rule(r), LabelSource{kind, 0.0, 3});
      ASSERT_TRUE(outcome.ok()) << outcome.error();
      EXPECT_GT(outcome.value().error.compared, 1000u);
      EXPECT_EQ(outcome.value().error.wrong, 0u) << volume::labelRuleName(r);
    }
}

TEST_F(SmallSyntheticScenario, HeavyNoiseShowsAsErrorAndOnlyTopFiveRulesUseASidecar) {
  auto evidence = scenario_->run(rule(volume::LabelRule::kEvidence), LabelSource{LabelSourceKind::kPixel, 0.7, 3});
  auto majority = scenario_->run(rule(volume::LabelRule::kMajority), LabelSource{LabelSourceKind::kPixel, 0.7, 3});
  ASSERT_TRUE(evidence.ok() && majority.ok());
  EXPECT_GT(evidence.value().error.fraction(), 0.2);
  EXPECT_LT(majority.value().error.fraction(), evidence.value().error.fraction());
  EXPECT_EQ(evidence.value().sidecar_bytes_per_voxel, 0.0);
  // The sidecar mirrors the geometry grid (same topology, 8-byte values): the same memory.
  const volume::LabeledVolume& geometry = scenario_->geometry();
  const double geometry_bytes =
      static_cast<double>(geometry.geometryMemoryBytes()) / static_cast<double>(geometry.allocatedVoxels());
  EXPECT_GT(majority.value().sidecar_bytes_per_voxel, 8.0);
  EXPECT_NEAR(majority.value().sidecar_bytes_per_voxel, geometry_bytes, 0.05 * geometry_bytes);
}

TEST_F(SmallSyntheticScenario, NoiseSourcesCorruptTheTruthAsDocumented) {
  auto clean = labelsFor(*sequence_, 3, LabelSource{LabelSourceKind::kPixel, 0.0, 5});
  ASSERT_TRUE(clean.ok());
  EXPECT_EQ(cv::countNonZero(clean.value().labels != sequence_->truth[3]), 0);

  auto cnn = labelsFor(*sequence_, 3, LabelSource{LabelSourceKind::kSimulatedCnn, 1.0, 5});
  ASSERT_TRUE(cnn.ok());
  const cv::Mat switched = cnn.value().labels != sequence_->truth[3];
  ASSERT_GT(cv::countNonZero(switched), 0);
  double low = 0, high = 0;
  cv::minMaxLoc(cnn.value().confidence, &low, &high, nullptr, nullptr, switched);
  EXPECT_FLOAT_EQ(static_cast<float>(high), 0.55f);  // switched regions are less sure

  auto constant = labelsFor(*sequence_, 3, LabelSource{LabelSourceKind::kSimulatedCnn, 1.0, 5, WeightMode::kConstant});
  ASSERT_TRUE(constant.ok());
  cv::minMaxLoc(constant.value().confidence, &low, &high);
  EXPECT_EQ(low, 1.0);

  EXPECT_FALSE(labelsFor(*sequence_, 999, LabelSource{}).ok());
  EXPECT_FALSE(labelsFor(*sequence_, 0, LabelSource{LabelSourceKind::kSegmenter}).ok());  // synthetic has none
}

TEST_F(SmallSyntheticScenario, DiagnosisSeesTheMetricsVoxelsAndErrors) {
  const LabelSource noisy{LabelSourceKind::kPixel, 0.6, 3};
  auto diagnosis = diagnoseLabels(*scenario_, rule(volume::LabelRule::kMajority), noisy);
  auto outcome = scenario_->run(rule(volume::LabelRule::kMajority), noisy);
  ASSERT_TRUE(diagnosis.ok()) << diagnosis.error();
  ASSERT_TRUE(outcome.ok()) << outcome.error();
  const LabelDiagnosis& d = diagnosis.value();
  EXPECT_EQ(d.voxels, outcome.value().error.compared);
  EXPECT_EQ(d.rule_wrong, outcome.value().error.wrong);
  EXPECT_GT(d.rule_wrong, 0u);
  std::size_t binned = 0, binned_wrong = 0;
  for (const DiagnosisBin& b : d.bins) binned += b.voxels, binned_wrong += b.rule_wrong;
  EXPECT_EQ(binned, d.voxels);
  EXPECT_EQ(binned_wrong, d.rule_wrong);
  EXPECT_EQ(d.bins.front().voxels, 0u);  // a voxel the reference labels was shown a label
  EXPECT_EQ(d.rule_wrong - d.rule_only_wrong, d.oracle_wrong - d.oracle_only_wrong);  // both wrong
  EXPECT_GT(d.border_voxels, 0u);
  EXPECT_LT(d.border_voxels, d.voxels / 2);
}

TEST_F(SmallSyntheticScenario, ExactCountOracleAgreesWithTheReferenceOnTheTruth) {
  // 12 frames: no count reaches the clamp and 5 slots hold every label a voxel sees, so the
  // majority rule is an exact count; only ties (the rule keeps the first label seen, the oracle
  // the first in legend order) may differ.
  auto d = diagnoseLabels(*scenario_, rule(volume::LabelRule::kMajority), LabelSource{});
  ASSERT_TRUE(d.ok()) << d.error();
  EXPECT_EQ(d.value().rule_wrong, 0u);
  EXPECT_LT(d.value().oracle_wrong, d.value().voxels / 50);
}

}  // namespace
}  // namespace semfuse::eval
