// The label fusion rules of label_rules.hpp on hand-made observation sequences: first the pure
// top-5 update and its sidecar packing, then each rule through integrate() and a map file round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <vector>

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/label_rules.hpp"
#include "semfuse/volume/map_file.hpp"

namespace semfuse::volume {
namespace {

struct Observation {
  LabelId label;
  float confidence;
};

// Runs a sequence through one rule on one voxel's state (packed label/score + sidecar).
struct VoxelState {
  LabelId label = kUnlabeled;
  float score = 0.0f;
  PackedLabelSidecar sidecar = 0;
  LabelCandidates candidates(float max_score = 16.0f) const {
    return unpackCandidates(label, score, sidecar, runnerUpQuantaPerUnit(max_score));
  }
};

VoxelState run(const LabelRuleConfig& config, const std::vector<Observation>& sequence) {
  VoxelState v;
  for (const Observation& o : sequence) applyLabelRule(config, v.label, v.score, &v.sidecar, o.label, o.confidence);
  return v;
}

LabelRuleConfig ruleConfig(LabelRule rule, float max_score = 16.0f) {
  VolumeParams params;
  params.label_rule = rule;
  params.max_label_score = max_score;
  return params.labelRuleConfig();
}

TEST(LabelRules, NamesParseBackAndUnknownNamesAreRefused) {
  for (LabelRule rule : {LabelRule::kEvidence, LabelRule::kMajority, LabelRule::kBayes})
    EXPECT_EQ(parseLabelRule(labelRuleName(rule)).value(), rule);
  auto bad = parseLabelRule("vote");
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("evidence, majority or bayes"), std::string::npos);
}

TEST(LabelRules, MemoryPerVoxelIsEightBytesForEvidenceAndSixteenForTopFive) {
  EXPECT_EQ(labelRuleBytesPerVoxel(LabelRule::kEvidence), 8u);
  EXPECT_EQ(labelRuleBytesPerVoxel(LabelRule::kMajority), 16u);
  EXPECT_EQ(labelRuleBytesPerVoxel(LabelRule::kBayes), 16u);
}

TEST(LabelRules, RunnerUpStepDividesOneObservationWhileSixtyThreeStepsReachTheClamp) {
  EXPECT_EQ(runnerUpQuantaPerUnit(16.0f), 3.0f);  // 63 steps of 1/3 = 21 >= 16
  EXPECT_EQ(runnerUpQuantaPerUnit(4.0f), 15.0f);
  EXPECT_EQ(runnerUpQuantaPerUnit(63.0f), 1.0f);
  EXPECT_EQ(runnerUpQuantaPerUnit(64.0f), 0.5f);  // one step = 2 observations
  EXPECT_EQ(runnerUpQuantaPerUnit(2048.0f), 1.0f / 33.0f);
}

TEST(LabelRules, SidecarPacksFourRunnersUpAsTenBitLabelsAndSixBitScores) {
  const float per_unit = runnerUpQuantaPerUnit(16.0f);
  LabelCandidates c;
  c.label[0] = 4, c.score[0] = 16.0f;
  c.label[1] = 1023, c.score[1] = 16.0f;  // the largest label and score a slot holds
  c.label[2] = 7, c.score[2] = 2.0f / 3.0f;
  c.label[3] = 150, c.score[3] = 5.0f;
  c.label[4] = 1, c.score[4] = 1.0f / 3.0f;
  const PackedLabelSidecar packed = packSidecar(c, per_unit);
  const LabelCandidates back = unpackCandidates(4, 16.0f, packed, per_unit);
  for (int i = 0; i < kLabelCandidates; ++i) {
    EXPECT_EQ(back.label[i], c.label[i]) << i;
    EXPECT_FLOAT_EQ(back.score[i], c.score[i]) << i;
  }
  // Slot 1 in the lowest 16 bits: label 1023 in bits 0-9, 48 steps of 1/3 in bits 10-15.
  EXPECT_EQ(static_cast<uint64_t>(packed) & 0xFFFFu, (48u << 10) | 1023u);
  EXPECT_EQ(packSidecar(LabelCandidates{}, per_unit), 0);  // nothing tracked: the grid's background
}

TEST(LabelRules, SidecarScoresRoundToTheNearestStepButATrackedLabelKeepsOne) {
  const float per_unit = runnerUpQuantaPerUnit(16.0f);
  LabelCandidates c;
  c.label[0] = 4, c.score[0] = 16.0f;
  c.label[1] = 5, c.score[1] = 1.2f;   // 3.6 steps -> 4
  c.label[2] = 6, c.score[2] = 0.05f;  // 0.15 steps: kept at one step, not dropped
  c.label[3] = 7, c.score[3] = 40.0f;  // beyond 63 steps (never happens under the clamp): saturates
  const LabelCandidates back = unpackCandidates(4, 16.0f, packSidecar(c, per_unit), per_unit);
  EXPECT_FLOAT_EQ(back.score[1], 4.0f / 3.0f);
  EXPECT_EQ(back.label[2], 6);
  EXPECT_FLOAT_EQ(back.score[2], 1.0f / 3.0f);
  EXPECT_FLOAT_EQ(back.score[3], 21.0f);
  EXPECT_EQ(back.label[4], kUnlabeled);
  EXPECT_EQ(back.score[4], 0.0f);
}

TEST(LabelRules, TopFiveRulesIgnoreLabelsBeyondTheSidecarsTenBits) {
  for (LabelRule rule : {LabelRule::kMajority, LabelRule::kBayes}) {
    const VoxelState v = run(ruleConfig(rule), {{5, 1.0f}, {1024, 1.0f}, {1024, 1.0f}, {65535, 1.0f}});
    EXPECT_EQ(v.label, 5);
    EXPECT_EQ(v.score, 1.0f);
    EXPECT_EQ(v.sidecar, 0);
  }
  const VoxelState evidence =
      run(ruleConfig(LabelRule::kEvidence), {{5, 1.0f}, {1024, 1.0f}, {1024, 1.0f}, {1024, 1.0f}});
  EXPECT_EQ(evidence.label, 1024);  // the paper's rule keeps 16-bit labels in the packed voxel
}

TEST(LabelRules, MajorityCountsEachLabelAndIgnoresConfidence) {
  const VoxelState v = run(ruleConfig(LabelRule::kMajority),
                           {{5, 0.2f}, {5, 0.2f}, {7, 1.0f}, {5, 0.2f}, {7, 1.0f}, {9, 1.0f}, {11, 0.5f}, {12, 1.0f}});
  const LabelCandidates c = v.candidates();
  EXPECT_EQ(v.label, 5);
  EXPECT_EQ(v.score, 3.0f);
  const LabelId labels[] = {5, 7, 9, 11, 12};
  const float counts[] = {3, 2, 1, 1, 1};
  for (int i = 0; i < kLabelCandidates; ++i) {
    EXPECT_EQ(c.label[i], labels[i]) << i;
    EXPECT_EQ(c.score[i], counts[i]) << i;
  }
}

TEST(LabelRules, SixthLabelErodesEveryEntryThenTakesAFreedSlot) {
  const auto config = ruleConfig(LabelRule::kMajority);
  VoxelState v = run(config, {{1, 1}, {1, 1}, {1, 1}, {2, 1}, {2, 1}, {3, 1}, {3, 1}, {4, 1}, {4, 1}, {5, 1}, {6, 1}});
  LabelCandidates c = v.candidates();
  const LabelId labels[] = {1, 2, 3, 4, kUnlabeled};
  const float counts[] = {2, 1, 1, 1, 0};  // Misra-Gries: the outsider's vote cancels one vote of each
  for (int i = 0; i < kLabelCandidates; ++i) {
    EXPECT_EQ(c.label[i], labels[i]) << i;
    EXPECT_EQ(c.score[i], counts[i]) << i;  // label 5's single count was used up
  }
  applyLabelRule(config, v.label, v.score, &v.sidecar, 6, 1.0f);
  c = v.candidates();
  EXPECT_EQ(c.label[4], 6);
  EXPECT_EQ(c.score[4], 1.0f);
}

// Every label with more than a sixth of the votes stays in the list: a label with 2 of every 9
// votes, the rest spread over 7 others arriving in between, wins. The former three slots track
// only labels above a quarter: there 2/9 is eroded away and the list ends as {7, 8}.
TEST(LabelRules, ALabelWithAFifthOfTheVotesAgainstSevenOthersWins) {
  std::vector<Observation> sequence;
  for (int cycle = 0; cycle < 10; ++cycle)
    for (LabelId id : {1, 2, 3, 4, 5, 1, 6, 7, 8}) sequence.push_back({id, 1.0f});
  EXPECT_EQ(run(ruleConfig(LabelRule::kMajority), sequence).label, 1);
  EXPECT_EQ(run(ruleConfig(LabelRule::kBayes), sequence).label, 1);
}

TEST(LabelRules, ClampShiftsAllScoresSoAChangedSceneIsRelearned) {
  const auto config = ruleConfig(LabelRule::kMajority, 4.0f);
  std::vector<Observation> sequence(10, {5, 1.0f});
  for (int i = 0; i < 4; ++i) sequence.push_back({7, 1.0f});
  VoxelState v = run(config, sequence);
  EXPECT_EQ(v.label, 5);  // 5 saturated at 4, 7 caught up to 4: a tie keeps the incumbent
  EXPECT_EQ(v.score, 4.0f);
  applyLabelRule(config, v.label, v.score, &v.sidecar, 7, 1.0f);
  const LabelCandidates c = v.candidates(4.0f);
  EXPECT_EQ(c.label[0], 7);
  EXPECT_EQ(c.score[0], 4.0f);
  EXPECT_EQ(c.label[1], 5);
  EXPECT_EQ(c.score[1], 3.0f);  // the shift keeps the difference of one observation
}

TEST(LabelRules, AWeightedOutsiderEntersWithTheEvidenceLeftOver) {
  LabelCandidates c;
  const float scores[] = {3.0f, 1.0f, 0.75f, 0.5f, 0.25f};
  for (int i = 0; i < kLabelCandidates; ++i) c.label[i] = static_cast<LabelId>(i + 1), c.score[i] = scores[i];
  accumulateTopLabels(c, 9, 0.75f, 16.0f);  // 0.25 taken from each, 5 is used up, 9 enters with 0.5
  // 9 (0.5) sorts above 4 (0.25); the stable sort keeps 3 (0.5) ahead of the newcomer.
  const LabelId labels[] = {1, 2, 3, 9, 4};
  const float after[] = {2.75f, 0.75f, 0.5f, 0.5f, 0.25f};
  for (int i = 0; i < kLabelCandidates; ++i) {
    EXPECT_EQ(c.label[i], labels[i]) << i;
    EXPECT_FLOAT_EQ(c.score[i], after[i]) << i;
  }
}

TEST(LabelRules, BayesWeighsConfidenceThroughTheCalibratedLikelihood) {
  const auto config = ruleConfig(LabelRule::kBayes);
  EXPECT_FLOAT_EQ(bayesIncrement(1.0f, config), 1.0f);
  EXPECT_FLOAT_EQ(bayesIncrement(0.0f, config), 0.0f);  // chance-level confidence is no evidence
  // L = 20, p_max = 0.9: p(0.3) = 0.05 + 0.85 * 0.3 = 0.305, log(0.305 / 0.695 * 19) / log(0.9 / 0.1 * 19).
  EXPECT_NEAR(bayesIncrement(0.3f, config), std::log(0.305 / 0.695 * 19) / std::log(171.0), 1e-5);

  // Two unsure votes for 5 against one sure vote for 7: majority counts 5, bayes believes 7,
  // evidence subtracts 7's confidence from 5 (score negative, label 5 until the next frame).
  const std::vector<Observation> sequence{{5, 0.3f}, {5, 0.3f}, {7, 1.0f}};
  EXPECT_EQ(run(ruleConfig(LabelRule::kMajority), sequence).label, 5);
  EXPECT_EQ(run(config, sequence).label, 7);
  const VoxelState evidence = run(ruleConfig(LabelRule::kEvidence), sequence);
  EXPECT_EQ(evidence.label, 5);
  EXPECT_NEAR(evidence.score, -0.4f, 1e-3f);
  EXPECT_EQ(evidence.sidecar, 0);  // evidence never touches a sidecar
}

// The integrator interpolates the bayes increment from a table of 1025 confidences instead of
// taking a logarithm per voxel: within 1e-5 of the exact increment everywhere.
TEST(LabelRules, TabulatedBayesIncrementIsWithinOneHundredThousandthOfTheExactOne) {
  const auto config = ruleConfig(LabelRule::kBayes);
  ASSERT_TRUE(config.bayes_increments);
  double worst = 0.0;
  for (int i = 0; i <= 100000; ++i) {
    const float w = static_cast<float>(i) / 100000.0f;
    worst = std::max(worst, std::abs(static_cast<double>(bayesIncrementFast(w, config)) - bayesIncrement(w, config)));
  }
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(worst, 0.0);  // the table is used
  EXPECT_EQ(bayesIncrementFast(1.0f, config), config.bayes_increments->back());
  EXPECT_EQ(bayesIncrementFast(2.0f, config), config.bayes_increments->back());  // clamped as bayesIncrement clamps
  EXPECT_FALSE(bayesIncrementFast(-0.5f, config) > 0.0f);                        // no evidence
  EXPECT_FALSE(ruleConfig(LabelRule::kMajority).bayes_increments);               // only bayes needs it
}

// applyLabelRule takes a shortcut when the voxel has no runner-up and sees its leader again (or
// its first label). Random sequences through it and through the whole candidate list
// (applyTopLabels) end in the same bits, for both top-5 rules and for a clamp that is reached.
TEST(LabelRules, ShortcutForTheLeaderGivesTheSameBitsAsTheCandidateList) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> confidence(0.0f, 1.0f);
  std::uniform_int_distribution<int> pick(0, 99);
  int shortcuts = 0;
  for (LabelRule rule : {LabelRule::kBayes, LabelRule::kMajority})
    for (float max_score : {16.0f, 3.0f}) {
      const auto config = ruleConfig(rule, max_score);
      for (int voxel = 0; voxel < 500; ++voxel) {
        VoxelState fast, full;
        const auto leader = static_cast<LabelId>(1 + voxel % 7);
        for (int frame = 0; frame < 80; ++frame) {
          // Mostly the leader, sometimes another label: runners-up come and are worn away.
          const int roll = pick(rng);
          const auto observed = static_cast<LabelId>(roll < 85 ? leader : 1 + roll % 9);
          const float w = confidence(rng);
          const bool shortcut = fast.sidecar == 0 && (fast.label == kUnlabeled || fast.label == observed);
          shortcuts += shortcut ? 1 : 0;
          applyLabelRule(config, fast.label, fast.score, &fast.sidecar, observed, w);
          const float increment = rule == LabelRule::kMajority ? 1.0f : bayesIncrementFast(w, config);
          if (increment > 0.0f) applyTopLabels(config, full.label, full.score, &full.sidecar, observed, increment);
          ASSERT_EQ(fast.label, full.label) << "voxel " << voxel << " frame " << frame;
          ASSERT_EQ(std::memcmp(&fast.score, &full.score, sizeof(float)), 0) << fast.score << " " << full.score;
          ASSERT_EQ(fast.sidecar, full.sidecar);
        }
      }
    }
  EXPECT_GT(shortcuts, 50000);  // most updates took it
}

// The paper's noise model on 2000 voxels seen 60 times each: every observation is switched with
// probability 0.6 to one of the 7 other labels, at full confidence. Counting the top-3 labels
// recovers nearly every voxel; evidence weighting, which lets each wrong label subtract, does not.
TEST(LabelRules, TopFiveRulesRemovePixelNoiseThatDefeatsEvidenceWeighting) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> coin(0.0f, 1.0f);
  std::uniform_int_distribution<int> other(0, 6);
  auto wrong_fraction = [&](LabelRule rule) {
    const auto config = ruleConfig(rule);
    int wrong = 0;
    const int voxels = 2000;
    for (int voxel = 0; voxel < voxels; ++voxel) {
      const LabelId truth = static_cast<LabelId>(1 + voxel % 8);
      VoxelState v;
      for (int frame = 0; frame < 60; ++frame) {
        LabelId observed = truth;
        if (coin(rng) < 0.6f) observed = static_cast<LabelId>(1 + (truth + other(rng)) % 8);
        applyLabelRule(config, v.label, v.score, &v.sidecar, observed, 1.0f);
      }
      wrong += v.label != truth;
    }
    return static_cast<double>(wrong) / voxels;
  };
  EXPECT_LT(wrong_fraction(LabelRule::kMajority), 0.01);
  EXPECT_LT(wrong_fraction(LabelRule::kBayes), 0.01);
  EXPECT_GT(wrong_fraction(LabelRule::kEvidence), 0.15);
}

// Through the integrator: a wall 1 m in front of the camera, the voxel straight ahead.
class LabelRuleInVolume : public ::testing::Test {
 protected:
  const PinholeIntrinsics k = testing::smallCamera();
  const cv::Mat depth = cv::Mat(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  const openvdb::Coord wall{0, 0, 100};

  void fuse(LabeledVolume& volume, LabelId id, float w, bool late = false) {
    const cv::Mat labels(120, 160, CV_16UC1, cv::Scalar(id));
    const cv::Mat confidence(120, 160, CV_32FC1, cv::Scalar(w));
    auto r = late ? integrateLabels(volume, depth, labels, confidence, k, Pose::Identity())
                  : integrate(volume, depth, cv::Mat(), labels, confidence, k, Pose::Identity());
    ASSERT_TRUE(r.ok()) << r.error();
  }
};

TEST_F(LabelRuleInVolume, MajorityKeepsRunnersUpInTheSidecarAndTheWinnerInTheVoxel) {
  VolumeParams params;
  params.label_rule = LabelRule::kMajority;
  LabeledVolume volume(params);
  ASSERT_NE(volume.labelSidecarGrid(), nullptr);
  fuse(volume, 5, 1.0f);
  fuse(volume, 7, 1.0f);
  fuse(volume, 7, 0.1f, /*late=*/true);  // a late segmentation reaches the same sidecar
  EXPECT_EQ(volume.voxel(wall).label, 7);
  EXPECT_EQ(volume.voxel(wall).score, 2.0f);
  const auto c =
      unpackCandidates(volume.voxel(wall).label, volume.voxel(wall).score,
                       volume.labelSidecarGrid()->tree().getValue(wall), runnerUpQuantaPerUnit(params.max_label_score));
  EXPECT_EQ(c.label[1], 5);
  EXPECT_EQ(c.score[1], 1.0f);
  EXPECT_EQ(volume.labelSidecarGrid()->tree().leafCount(), volume.geometryGrid().tree().leafCount());
  EXPECT_GT(volume.labelSidecarMemoryBytes(), 0u);

  VolumeParams evidence_params;
  evidence_params.label_rule = LabelRule::kEvidence;
  LabeledVolume evidence{evidence_params};
  EXPECT_EQ(evidence.labelSidecarGrid(), nullptr);
  EXPECT_EQ(evidence.labelSidecarMemoryBytes(), 0u);
}

TEST_F(LabelRuleInVolume, MapFileKeepsTheRuleAndTheSidecar) {
  VolumeParams params;
  params.label_rule = LabelRule::kBayes;
  params.label_classes = 9;
  LabeledVolume volume(params);
  fuse(volume, 5, 1.0f);
  fuse(volume, 7, 0.6f);
  const auto folder = std::filesystem::temp_directory_path() / ("semfuse_label_rules_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const auto path = folder / "map.vdb";
  ASSERT_TRUE(saveMap(volume, LabelLegend{"test", {}, {}}, path).ok());
  auto loaded = loadMap(path);
  std::filesystem::remove_all(folder);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const LabeledVolume& back = loaded.value().volume;
  EXPECT_EQ(back.params().label_rule, LabelRule::kBayes);
  EXPECT_EQ(back.params().label_classes, 9);
  ASSERT_NE(back.labelSidecarGrid(), nullptr);
  EXPECT_EQ(back.labelSidecarGrid()->tree().getValue(wall), volume.labelSidecarGrid()->tree().getValue(wall));
  EXPECT_NE(back.labelSidecarGrid()->tree().getValue(wall), 0);
  EXPECT_EQ(back.voxel(wall).label, 5);
}

}  // namespace
}  // namespace semfuse::volume
