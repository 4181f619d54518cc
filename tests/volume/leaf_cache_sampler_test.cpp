// LeafCacheSampler against VolumeSampler on a fused map with colour: the same TSDF, intensity and
// gradients, to the bit, at points inside leaves and on cells that straddle leaves, the same
// "unobserved" answers, and the same again once its table has grown and every leaf is cached.
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/leaf_cache_sampler.hpp"
#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::volume {
namespace {
using testing::lookAt;
using testing::smallCamera;

// A colour pattern that changes across the image, so that the fused intensity has gradients.
cv::Mat patternImage(const PinholeIntrinsics& k) {
  cv::Mat color(k.height, k.width, CV_8UC3);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u)
      color.at<cv::Vec3b>(v, u) =
          cv::Vec3b(static_cast<uint8_t>(3 * u), static_cast<uint8_t>(5 * v), static_cast<uint8_t>((u * v) % 251));
  return color;
}

// A plane at z = 1.2 and a sphere before it, seen from three poses.
LabeledVolume fusedScene(bool with_color) {
  VolumeParams params;
  params.integrate_color = with_color;
  LabeledVolume volume(params);
  const PinholeIntrinsics k = smallCamera();
  const Eigen::Vector3d centre(0.05, 0.0, 0.9);
  for (const Eigen::Vector3d& eye :
       {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.2, 0.1, 0.05), Eigen::Vector3d(-0.2, -0.1, 0.1)}) {
    const Pose pose = lookAt(eye, Eigen::Vector3d(0.0, 0.0, 1.2));
    cv::Mat depth = testing::renderPlane(k, pose, Eigen::Vector3d(0, 0, -1), -1.2);
    const cv::Mat sphere = testing::renderSphere(k, pose, centre, 0.12);
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        const float s = sphere.at<float>(v, u);
        if (s > 0.0f && s < depth.at<float>(v, u)) depth.at<float>(v, u) = s;
      }
    EXPECT_TRUE(integrate(volume, depth, with_color ? patternImage(k) : cv::Mat(), k, pose).ok());
  }
  return volume;
}

// Points near the fused surfaces and in the unobserved space around them, a tenth of them on
// cells whose corners lie in different leaves.
std::vector<Eigen::Vector3f> samplePoints(double voxel) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> x(-0.6f, 0.6f), y(-0.45f, 0.45f), z(0.7f, 1.35f), within(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 40000; ++i) {
    Eigen::Vector3f p(x(random), y(random), z(random));
    if (i % 10 == 0) {  // in the last cell of a leaf along x: its corners straddle two leaves
      const float cell = std::floor(p.x() / static_cast<float>(voxel));
      const float leaf_end = (std::floor(cell / 8.0f) * 8.0f + 7.0f + within(random)) * static_cast<float>(voxel);
      p.x() = leaf_end;
    }
    points.push_back(p);
  }
  return points;
}

TEST(LeafCacheSampler, SamplesTheMapExactlyAsVolumeSamplerDoes) {
  const LabeledVolume volume = fusedScene(/*with_color=*/true);
  ASSERT_NE(volume.colorGrid(), nullptr);
  VolumeSampler reference(volume);
  LeafCacheSampler cached(volume);
  const std::vector<Eigen::Vector3f> points = samplePoints(volume.voxelSize());
  std::size_t valid = 0, straddling = 0, leaves_after_first_pass = 0;
  for (int pass = 0; pass < 2; ++pass) {
    for (const Eigen::Vector3f& p : points) {
      float d0 = 0, d1 = 0, i0 = 0, i1 = 0;
      Eigen::Vector3f g0, g1, ig0, ig1;
      bool c0 = false, c1 = false;
      const bool ok0 = reference.tsdfAndIntensity(p, d0, g0, i0, ig0, c0);
      const bool ok1 = cached.tsdfAndIntensity(p, d1, g1, i1, ig1, c1);
      ASSERT_EQ(ok0, ok1) << "at " << p.transpose();
      if (!ok0) continue;
      ASSERT_TRUE(c1);
      ASSERT_EQ(d0, d1) << "at " << p.transpose();
      ASSERT_EQ(g0, g1) << "at " << p.transpose();
      ASSERT_EQ(i0, i1) << "at " << p.transpose();
      ASSERT_EQ(ig0, ig1) << "at " << p.transpose();
      float d2 = 0;
      Eigen::Vector3f g2;
      ASSERT_TRUE(cached.tsdfAndGradient(p, d2, g2));
      ASSERT_EQ(d0, d2);
      ASSERT_EQ(g0, g2);
      if (pass == 0) {
        ++valid;
        const int base_x = static_cast<int>(std::floor(p.x() / static_cast<float>(volume.voxelSize())));
        straddling += (base_x & 7) == 7;
      }
    }
    if (pass == 0) leaves_after_first_pass = cached.leavesLookedUp();
  }
  // Enough of each kind to mean something: observed cells, cells across leaves, and more leaf
  // origins than the table's first size holds (so it grew, and kept its entries).
  EXPECT_GT(valid, 3000u);
  EXPECT_GT(straddling, 300u);
  EXPECT_GT(leaves_after_first_pass, 1000u);
  EXPECT_EQ(cached.leavesLookedUp(), leaves_after_first_pass);  // the second pass found every leaf cached
}

TEST(LeafCacheSampler, WithoutColourTheTsdfIsTheSameAndThereIsNoIntensity) {
  const LabeledVolume volume = fusedScene(/*with_color=*/false);
  ASSERT_EQ(volume.colorGrid(), nullptr);
  VolumeSampler reference(volume);
  LeafCacheSampler cached(volume);
  std::size_t valid = 0;
  for (const Eigen::Vector3f& p : samplePoints(volume.voxelSize())) {
    float d0 = 0, d1 = 0, intensity = 0;
    Eigen::Vector3f g0, g1, intensity_gradient;
    bool has_intensity = true;
    const bool ok0 = reference.tsdfAndGradient(p, d0, g0);
    ASSERT_EQ(ok0, cached.tsdfAndIntensity(p, d1, g1, intensity, intensity_gradient, has_intensity));
    if (!ok0) continue;
    EXPECT_FALSE(has_intensity);
    ASSERT_EQ(d0, d1);
    ASSERT_EQ(g0, g1);
    ++valid;
  }
  EXPECT_GT(valid, 3000u);
}

TEST(LeafCacheSampler, NonFiniteAndFarPointsAreUnobserved) {
  const LabeledVolume volume = fusedScene(/*with_color=*/true);
  LeafCacheSampler cached(volume);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(nan, 0, 1), Eigen::Vector3f(0, inf, 1), Eigen::Vector3f(0, 0, -inf),
                                   Eigen::Vector3f(3e7f, 0, 1), Eigen::Vector3f(0, -1e30f, 1)}) {
    float d = 0;
    Eigen::Vector3f g;
    EXPECT_FALSE(cached.tsdfAndGradient(p, d, g)) << p.transpose();
  }
  // A point on the plane still reads as observed afterwards.
  float d = 1;
  Eigen::Vector3f g;
  EXPECT_TRUE(cached.tsdfAndGradient(Eigen::Vector3f(0.3f, 0.25f, 1.2f), d, g));
  EXPECT_LT(std::abs(d), 0.005f);
}

}  // namespace
}  // namespace semfuse::volume
