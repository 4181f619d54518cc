// The label noise of semfuse-segmenter's noise backend: how many pixels change, to what, and
// that a seed reproduces a run.
#include <algorithm>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/segmentation/noise_model.hpp"

namespace semfuse::segmentation {
namespace {

// 200x200: four quadrants labelled 1..4, with a 20-pixel unlabeled band at the top.
Segmentation quadrants() {
  Segmentation s;
  s.labels.create(200, 200, CV_16UC1);
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 200; ++c)
      s.labels.at<uint16_t>(r, c) = r < 20 ? 0 : static_cast<uint16_t>(1 + (r >= 110) * 2 + (c >= 100));
  s.confidence = cv::Mat(s.labels.size(), CV_32FC1, cv::Scalar(0.6F));
  return s;
}

NoiseParams pixelParams(double p, uint64_t seed) { return {NoiseModel::kPixel, p, seed, {1, 2, 3, 4, 5, 6, 7, 8}}; }

TEST(PixelNoise, SwitchesAboutPOfTheLabeledPixelsToAnotherCandidate) {
  const Segmentation clean = quadrants();
  auto noisy = addLabelNoise(clean, pixelParams(0.3, 7), 42);
  ASSERT_TRUE(noisy.ok()) << noisy.error();
  const cv::Mat& labels = noisy.value().labels;
  int labeled = 0, switched = 0;
  std::map<uint16_t, int> drawn;
  for (int r = 0; r < 200; ++r) {
    for (int c = 0; c < 200; ++c) {
      const uint16_t before = clean.labels.at<uint16_t>(r, c);
      const uint16_t after = labels.at<uint16_t>(r, c);
      const float confidence = noisy.value().confidence.at<float>(r, c);
      if (before == 0) {
        EXPECT_EQ(after, 0) << "an unlabeled pixel got a label at " << r << "," << c;
        continue;
      }
      ++labeled;
      if (after != before) {
        ++switched;
        ++drawn[after];
        EXPECT_GE(after, 1);
        EXPECT_LE(after, 8);
        EXPECT_EQ(confidence, 1.0F) << "a wrong label must come with maximum confidence";
      } else {
        EXPECT_EQ(confidence, 0.6F) << "an untouched pixel keeps its confidence";
      }
    }
  }
  // 36000 labeled pixels: the binomial standard deviation of the fraction is 0.0024.
  EXPECT_NEAR(static_cast<double>(switched) / labeled, 0.3, 0.012);
  // Wrong labels are uniform over the 7 others: labels 5..8 are never the original, so each
  // gets 1/7 of the switches.
  for (uint16_t label = 5; label <= 8; ++label) {
    EXPECT_NEAR(drawn[label] / static_cast<double>(switched), 1.0 / 7.0, 0.02) << "label " << label;
  }
}

TEST(PixelNoise, SameSeedAndFrameReproduceOtherwiseDiffer) {
  const Segmentation clean = quadrants();
  const cv::Mat a = addLabelNoise(clean, pixelParams(0.3, 7), 42).value().labels;
  const cv::Mat b = addLabelNoise(clean, pixelParams(0.3, 7), 42).value().labels;
  const cv::Mat other_seed = addLabelNoise(clean, pixelParams(0.3, 8), 42).value().labels;
  const cv::Mat other_frame = addLabelNoise(clean, pixelParams(0.3, 7), 43).value().labels;
  EXPECT_EQ(cv::countNonZero(a != b), 0);
  EXPECT_GT(cv::countNonZero(a != other_seed), 1000);
  EXPECT_GT(cv::countNonZero(a != other_frame), 1000);
}

TEST(PixelNoise, ZeroProbabilityChangesNothingAndOneChangesEveryLabeledPixel) {
  const Segmentation clean = quadrants();
  EXPECT_EQ(cv::countNonZero(addLabelNoise(clean, pixelParams(0.0, 1), 0).value().labels != clean.labels), 0);
  const cv::Mat all = addLabelNoise(clean, pixelParams(1.0, 1), 0).value().labels;
  EXPECT_EQ(cv::countNonZero(all != clean.labels), 200 * 180);
}

TEST(PixelNoise, RejectsBadParameters) {
  const Segmentation clean = quadrants();
  EXPECT_FALSE(addLabelNoise(clean, {NoiseModel::kPixel, 0.3, 0, {1}}, 0).ok());
  EXPECT_FALSE(addLabelNoise(clean, {NoiseModel::kPixel, 1.5, 0, {1, 2}}, 0).ok());
  Segmentation wrong_type = clean;
  clean.labels.convertTo(wrong_type.labels, CV_32S);
  EXPECT_FALSE(addLabelNoise(wrong_type, pixelParams(0.3, 0), 0).ok());
}

TEST(RegionNoise, SwitchesWholeRegionsAboutPOfThem) {
  // A 20x20 checkerboard of 10-pixel cells with labels 1 and 2: 400 separate regions.
  Segmentation clean;
  clean.labels.create(200, 200, CV_16UC1);
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 200; ++c) clean.labels.at<uint16_t>(r, c) = ((r / 10 + c / 10) % 2) ? 2 : 1;
  auto noisy = addLabelNoise(clean, {NoiseModel::kRegion, 0.3, 5, {1, 2, 3, 4}}, 0);
  ASSERT_TRUE(noisy.ok()) << noisy.error();
  int switched_cells = 0;
  for (int cell_r = 0; cell_r < 20; ++cell_r) {
    for (int cell_c = 0; cell_c < 20; ++cell_c) {
      const cv::Rect cell(cell_c * 10, cell_r * 10, 10, 10);
      const cv::Mat before = clean.labels(cell);
      const cv::Mat after = noisy.value().labels(cell);
      std::set<uint16_t> values(after.begin<uint16_t>(), after.end<uint16_t>());
      ASSERT_EQ(values.size(), 1u) << "region " << cell_r << "," << cell_c << " was split";
      if (*values.begin() != before.at<uint16_t>(0, 0)) ++switched_cells;
    }
  }
  // 400 regions: the standard deviation of the switched fraction is 0.023.
  EXPECT_NEAR(switched_cells / 400.0, 0.3, 0.08);
}

}  // namespace
}  // namespace semfuse::segmentation

namespace semfuse::segmentation {
namespace {

// The quadrants as four instances of ids 10, 20, 30, 40, none in the unlabeled band.
Segmentation panopticQuadrants() {
  Segmentation s = quadrants();
  s.instances = cv::Mat(s.labels.size(), CV_16UC1, cv::Scalar(0));
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 200; ++c)
      if (const uint16_t label = s.labels.at<uint16_t>(r, c)) s.instances.at<uint16_t>(r, c) = label * 10;
  return s;
}

TEST(InstanceNoise, RenumbersTheIdsAndErodesEveryMask) {
  const Segmentation clean = panopticQuadrants();
  NoiseParams params = pixelParams(0.0, 3);
  params.instance_erosion = 2;
  auto noisy = addLabelNoise(clean, params, 5);
  ASSERT_TRUE(noisy.ok()) << noisy.error();
  const cv::Mat& ids = noisy.value().instances;
  ASSERT_EQ(ids.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(noisy.value().labels, clean.labels, cv::NORM_INF), 0.0);  // p = 0: labels unchanged
  // Each clean instance maps to one new id in 1..4, all four different: a permutation.
  std::map<uint16_t, std::set<uint16_t>> renamed;
  int lost = 0;
  for (int r = 0; r < 200; ++r)
    for (int c = 0; c < 200; ++c) {
      const uint16_t before = clean.instances.at<uint16_t>(r, c), after = ids.at<uint16_t>(r, c);
      if (after == 0) {
        lost += before != 0;
        continue;
      }
      ASSERT_NE(before, 0) << "an instance grew into (" << r << ", " << c << ")";
      renamed[before].insert(after);
    }
  ASSERT_EQ(renamed.size(), 4u);
  std::set<uint16_t> used;
  for (const auto& [before, after] : renamed) {
    ASSERT_EQ(after.size(), 1u) << before;
    EXPECT_GE(*after.begin(), 1);
    EXPECT_LE(*after.begin(), 4);
    used.insert(*after.begin());
  }
  EXPECT_EQ(used.size(), 4u);
  // Two pixels off each side of every mask (the image border is no mask border for erode).
  EXPECT_EQ(ids.at<uint16_t>(60, 98), 0);
  EXPECT_NE(ids.at<uint16_t>(60, 97), 0);
  EXPECT_EQ(ids.at<uint16_t>(21, 50), 0);
  EXPECT_NE(ids.at<uint16_t>(22, 50), 0);
  EXPECT_GT(lost, 4 * 180);
  // Another frame renumbers differently sooner or later; the same frame the same way.
  auto again = addLabelNoise(clean, params, 5);
  EXPECT_EQ(cv::norm(again.value().instances, ids, cv::NORM_INF), 0.0);
  bool differs = false;
  for (uint64_t seq = 6; seq < 16 && !differs; ++seq)
    differs = cv::norm(addLabelNoise(clean, params, seq).value().instances, ids, cv::NORM_INF) != 0.0;
  EXPECT_TRUE(differs);
}

TEST(InstanceNoise, ClassOnlySegmentationsStayWithoutInstancesAndBadMapsAreRefused) {
  auto noisy = addLabelNoise(quadrants(), pixelParams(0.3, 1), 0);
  ASSERT_TRUE(noisy.ok());
  EXPECT_TRUE(noisy.value().instances.empty());
  Segmentation bad = panopticQuadrants();
  bad.instances = cv::Mat(10, 10, CV_16UC1, cv::Scalar(1));
  EXPECT_FALSE(addLabelNoise(bad, pixelParams(0.3, 1), 0).ok());
  NoiseParams negative = pixelParams(0.3, 1);
  negative.instance_erosion = -1;
  EXPECT_FALSE(addLabelNoise(panopticQuadrants(), negative, 0).ok());
}

}  // namespace
}  // namespace semfuse::segmentation
