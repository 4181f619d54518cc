// The AVX2 integration kernel against the scalar one: the same frames integrated with each must
// give the same volume bit for bit (packed voxels, colours, label sidecars, active masks) and the
// same statistics, for every kernel variant (depth only, + colour, + labels, late labels) and the
// inputs that exercise its edges: invalid depth of every kind, colour in the last image column,
// strided (ROI) images, labels at lower resolution, zero/NaN confidences, background labels.
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "grid_compare.hpp"

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"

namespace semfuse::volume {
namespace {

using semfuse::testing::expectSameGrid;
using testing::lookAt;
using testing::smallCamera;

// Restores the process-wide kernel choice when a test ends.
class KernelChoice {
 public:
  KernelChoice() : saved_(integrationKernel()) {}
  ~KernelChoice() { setIntegrationKernel(saved_); }
  KernelChoice(const KernelChoice&) = delete;
  KernelChoice& operator=(const KernelChoice&) = delete;

 private:
  IntegrationKernel saved_;
};

struct TestFrame {
  cv::Mat depth, color, labels, confidence;
  Pose pose;
};

// A sphere in front of a tilted wall, seen from a camera moving around them; depth with a few
// percent of invalid pixels (0, NaN, beyond max_depth), a colour gradient with per-pixel noise,
// labels by region at half resolution with varied confidences, some of them background (7),
// unlabeled or beyond 1023, zero or NaN. Every image is a view into a larger buffer, so rows
// are strided.
// labels_size: the label image's size (the depth's, a power-of-two fraction, or any other).
std::vector<TestFrame> makeSequence(int frames, unsigned seed, cv::Size labels_size) {
  const PinholeIntrinsics k = smallCamera();
  const Eigen::Vector3d centre(0.05, 0.0, 1.1);
  const double radius = 0.2;
  const Eigen::Vector3d wall_normal = Eigen::Vector3d(0.2, -0.1, -1).normalized();
  const double wall_offset = wall_normal.dot(Eigen::Vector3d(0, 0, 1.5));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<TestFrame> sequence;
  for (int i = 0; i < frames; ++i) {
    const double angle = 0.35 * i;
    const Eigen::Vector3d eye(0.25 * std::sin(angle), 0.15 * std::cos(1.3 * angle), 0.1 * i / frames);
    TestFrame f;
    f.pose = lookAt(eye, centre);
    const cv::Mat sphere = testing::renderSphere(k, f.pose, centre, radius);
    const cv::Mat wall = testing::renderPlane(k, f.pose, wall_normal, wall_offset);
    cv::Mat depth_buffer(k.height + 4, k.width + 7, CV_32FC1, cv::Scalar(0.5));
    f.depth = depth_buffer(cv::Rect(3, 2, k.width, k.height));
    cv::Mat color_buffer(k.height + 2, k.width + 5, CV_8UC3, cv::Scalar(1, 2, 3));
    f.color = color_buffer(cv::Rect(5, 1, k.width, k.height));
    cv::Mat label_buffer(labels_size.height + 1, labels_size.width + 3, CV_16UC1, cv::Scalar(99));
    f.labels = label_buffer(cv::Rect(cv::Point(1, 1), labels_size));
    cv::Mat confidence_buffer(labels_size.height + 2, labels_size.width + 1, CV_32FC1, cv::Scalar(-1));
    f.confidence = confidence_buffer(cv::Rect(cv::Point(0, 2), labels_size));
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        const float s = sphere.at<float>(v, u), w = wall.at<float>(v, u);
        float d = s > 0 && (w <= 0 || s < w) ? s : w;
        const float r = unit(rng);
        if (r < 0.02f) d = 0.0f;
        else if (r < 0.04f) d = std::numeric_limits<float>::quiet_NaN();
        else if (r < 0.05f) d = 65.535f;
        else d += 0.004f * (unit(rng) - 0.5f);  // sensor noise: sdf values off the voxel grid
        f.depth.at<float>(v, u) = d;
        f.color.at<cv::Vec3b>(v, u) = cv::Vec3b(static_cast<uint8_t>(u + 30 * i), static_cast<uint8_t>(2 * v),
                                                static_cast<uint8_t>(255 * unit(rng)));
      }
    for (int v = 0; v < f.labels.rows; ++v)
      for (int u = 0; u < f.labels.cols; ++u) {
        const float r = unit(rng);
        f.labels.at<uint16_t>(v, u) = r < 0.1f    ? 7
                                      : r < 0.15f ? 0
                                      : r < 0.17f ? 1500  // beyond the top-5 rules' 10-bit runners-up
                                                  : static_cast<uint16_t>(1 + (u / 10 + v / 15 + i % 3) % 5);
        const float c = unit(rng);
        f.confidence.at<float>(v, u) = c < 0.05f   ? 0.0f
                                       : c < 0.08f ? std::numeric_limits<float>::quiet_NaN()
                                                   : 0.3f + 0.7f * unit(rng);
      }
    sequence.push_back(f);
  }
  return sequence;
}

enum class Inputs { kDepth, kDepthColor, kDepthColorLabels, kDepthColorThenLateLabels };

struct KernelRun {
  LabeledVolume volume;
  std::vector<IntegrationStats> stats;
};

KernelRun integrateWith(IntegrationKernel kernel, const VolumeParams& params, const std::vector<TestFrame>& frames,
                        Inputs inputs) {
  EXPECT_TRUE(setIntegrationKernel(kernel));
  KernelRun run{LabeledVolume(params), {}};
  const PinholeIntrinsics k = smallCamera();
  for (const TestFrame& f : frames) {
    const cv::Mat color = inputs == Inputs::kDepth ? cv::Mat() : f.color;
    const bool labels_now = inputs == Inputs::kDepthColorLabels;
    auto stats = integrate(run.volume, f.depth, color, labels_now ? f.labels : cv::Mat(),
                           labels_now ? f.confidence : cv::Mat(), k, f.pose);
    EXPECT_TRUE(stats.ok()) << stats.error();
    if (stats) run.stats.push_back(stats.value());
    if (inputs == Inputs::kDepthColorThenLateLabels) {
      auto late = integrateLabels(run.volume, f.depth, f.labels, f.confidence, k, f.pose);
      EXPECT_TRUE(late.ok()) << late.error();
      if (late) run.stats.push_back(late.value());
    }
  }
  return run;
}

void expectSameRuns(const KernelRun& scalar, const KernelRun& wide) {
  expectSameGrid(&scalar.volume.geometryGrid(), &wide.volume.geometryGrid(), "geometry");
  expectSameGrid(scalar.volume.colorGrid(), wide.volume.colorGrid(), "colour");
  expectSameGrid(scalar.volume.labelSidecarGrid(), wide.volume.labelSidecarGrid(), "label sidecar");
  ASSERT_EQ(scalar.stats.size(), wide.stats.size());
  for (std::size_t i = 0; i < scalar.stats.size(); ++i) {
    EXPECT_EQ(scalar.stats[i].voxels_updated, wide.stats[i].voxels_updated) << "call " << i;
    EXPECT_EQ(scalar.stats[i].voxels_labeled, wide.stats[i].voxels_labeled) << "call " << i;
    EXPECT_EQ(scalar.stats[i].leaves_touched, wide.stats[i].leaves_touched) << "call " << i;
  }
}

struct Variant {
  Inputs inputs;
  LabelRule rule;
  cv::Size labels_size;   // the depth is 160x120
  bool background_label;  // label 7 is background (else only 0 is ignored)
};

class KernelsAgree : public ::testing::TestWithParam<Variant> {};

TEST_P(KernelsAgree, VoxelForVoxel) {
  if (!integrationKernelAvailable(IntegrationKernel::kAvx2)) GTEST_SKIP() << "this CPU or build has no AVX2 kernel";
  const KernelChoice restore;
  const auto [inputs, rule, labels_size, background_label] = GetParam();
  VolumeParams params;
  params.label_rule = rule;
  if (background_label) params.background_labels = {7};
  params.max_weight = 6;  // reached within the sequence: the clamp is exercised
  const std::vector<TestFrame> frames = makeSequence(10, 42, labels_size);
  const KernelRun scalar = integrateWith(IntegrationKernel::kScalar, params, frames, inputs);
  const KernelRun wide = integrateWith(IntegrationKernel::kAvx2, params, frames, inputs);
  // The scene must be non-trivial for the comparison to mean anything.
  ASSERT_GT(scalar.volume.observedVoxels(), 50000u);
  std::size_t labeled = 0;
  for (const IntegrationStats& s : scalar.stats) labeled += s.voxels_labeled;
  if (inputs == Inputs::kDepthColorLabels || inputs == Inputs::kDepthColorThenLateLabels) {
    EXPECT_GT(labeled, 50000u);
  }
  expectSameRuns(scalar, wide);
}

INSTANTIATE_TEST_SUITE_P(
    AllVariants, KernelsAgree,
    ::testing::Values(Variant{Inputs::kDepth, LabelRule::kEvidence, {80, 60}, true},
                      Variant{Inputs::kDepthColor, LabelRule::kEvidence, {80, 60}, true},
                      Variant{Inputs::kDepthColorLabels, LabelRule::kEvidence, {80, 60}, true},
                      Variant{Inputs::kDepthColorLabels, LabelRule::kEvidence, {160, 120}, false},
                      Variant{Inputs::kDepthColorLabels, LabelRule::kEvidence, {107, 90}, true},
                      Variant{Inputs::kDepthColorThenLateLabels, LabelRule::kEvidence, {80, 60}, true},
                      Variant{Inputs::kDepthColorThenLateLabels, LabelRule::kEvidence, {160, 120}, false},
                      Variant{Inputs::kDepthColorLabels, LabelRule::kBayes, {80, 60}, true},
                      Variant{Inputs::kDepthColorThenLateLabels, LabelRule::kMajority, {107, 90}, false}));

TEST(IntegrationKernel, ScalarIsAlwaysAvailableAndSelectable) {
  const KernelChoice restore;
  EXPECT_TRUE(integrationKernelAvailable(IntegrationKernel::kScalar));
  EXPECT_TRUE(setIntegrationKernel(IntegrationKernel::kScalar));
  EXPECT_EQ(integrationKernel(), IntegrationKernel::kScalar);
  EXPECT_STREQ(integrationKernelName(IntegrationKernel::kScalar), "scalar");
  // The AVX2 kernel is selectable exactly where it is available.
  EXPECT_EQ(setIntegrationKernel(IntegrationKernel::kAvx2), integrationKernelAvailable(IntegrationKernel::kAvx2));
}

// A frame integrated in batches, with a pause between them, gives the volume and statistics of one
// integrated at once; the pause comes once between each two batches of kLeavesPerBatch leaves.
TEST(IntegrationBatches, PausesBetweenBatchesChangeNothing) {
  VolumeParams params;
  const std::vector<TestFrame> frames = makeSequence(6, 7, {80, 60});
  const PinholeIntrinsics k = smallCamera();
  KernelRun whole{LabeledVolume(params), {}}, batched{LabeledVolume(params), {}};
  std::size_t pauses = 0, expected_pauses = 0;
  for (const TestFrame& f : frames) {
    auto at_once = integrate(whole.volume, f.depth, f.color, f.labels, f.confidence, k, f.pose);
    auto in_batches = integrate(batched.volume, f.depth, f.color, f.labels, f.confidence, k, f.pose, [&] { ++pauses; });
    ASSERT_TRUE(at_once.ok() && in_batches.ok());
    whole.stats.push_back(at_once.value());
    batched.stats.push_back(in_batches.value());
    const std::size_t leaves = in_batches.value().leaves_touched;
    expected_pauses += leaves == 0 ? 0 : (leaves - 1) / kLeavesPerBatch;
  }
  ASSERT_GT(expected_pauses, 0u) << "the frames must touch more than one batch of leaves";
  EXPECT_EQ(pauses, expected_pauses);
  expectSameRuns(whole, batched);
}

}  // namespace
}  // namespace semfuse::volume
