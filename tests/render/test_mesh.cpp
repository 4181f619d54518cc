// Marching-cubes mesh of a fused sphere and plane against the analytic surface.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "fused_scene.hpp"
#include "semfuse/render/mesh.hpp"

namespace semfuse::render {
namespace {

constexpr double kVoxel = 0.01;

class MeshTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_.add({"plane", synthetic::OrientedBox{{0, 0, -0.1}, {1.0, 1.0, 0.1}, Eigen::Matrix3d::Identity()}, 1,
                {200, 180, 150}, synthetic::Texture::kChecker});
    scene_.add({"sphere", synthetic::Sphere{{0.0, 0.0, 0.3}, 0.25}, 7, {200, 40, 40}, synthetic::Texture::kNoise});
    volume::VolumeParams p;
    p.voxel_size = kVoxel;
    p.truncation = 0.04;
    volume_ = volume::LabeledVolume(p);
    testing::fuse(volume_, scene_, testing::arcAround({0, 0, 0.2}, 1.1, 0.6, 8, 2.5));
  }
  synthetic::LabeledScene scene_;
  volume::LabeledVolume volume_;
};

TEST_F(MeshTest, VerticesLieWithinOneVoxelOfTheSurface) {
  const auto mesh = extractMesh(volume_);
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  const LabeledMesh& m = mesh.value();
  ASSERT_GT(m.vertices.size(), 5000u);
  ASSERT_GT(m.triangles.size(), m.vertices.size());
  double worst = 0.0;
  int label_matches = 0;
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const auto truth = scene_.nearestSurface(m.vertices[i].cast<double>());
    worst = std::max(worst, std::abs(truth.signed_distance));
    label_matches += m.labels[i] == truth.label ? 1 : 0;
  }
  EXPECT_LT(worst, kVoxel);
  EXPECT_GT(label_matches, 0.98 * m.vertices.size());
  EXPECT_EQ(m.colors.size(), m.vertices.size());
}

TEST_F(MeshTest, TrianglesFaceFreeSpace) {
  const LabeledMesh m = extractMesh(volume_).value();
  size_t agree = 0;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3f face = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    agree += face.dot(m.normals[t[0]] + m.normals[t[1]] + m.normals[t[2]]) > 0 ? 1 : 0;
  }
  EXPECT_GT(agree, 0.99 * m.triangles.size());  // counter-clockwise seen from outside
}

TEST_F(MeshTest, BoundsRestrictTheMesh) {
  MeshOptions options;
  options.bounds = WorldBounds{{-0.5, -0.5, 0.2}, {0.5, 0.5, 1.0}};  // the upper part of the sphere only
  const LabeledMesh m = extractMesh(volume_, options).value();
  ASSERT_GT(m.vertices.size(), 500u);
  for (const auto& v : m.vertices) ASSERT_GT(v.z(), 0.2f - 1.5f * kVoxel);
  // Only sphere up there: no floor vertex (a few sphere voxels may still be unlabeled).
  EXPECT_EQ(std::count(m.labels.begin(), m.labels.end(), LabelId{1}), 0);
  EXPECT_GT(std::count(m.labels.begin(), m.labels.end(), LabelId{7}), 0.95 * m.labels.size());
  options.bounds = WorldBounds{{0, 0, 0}, {0, 1, 1}};
  EXPECT_FALSE(extractMesh(volume_, options).ok());
}

TEST(Mesh, UnobservedSpaceProducesNoSurface) {
  // One frontal view of a plane: the band ends where observation ends; no wall of triangles may
  // appear along the back of the band or at the edges of the view.
  synthetic::LabeledScene scene;
  scene.add({"wall", synthetic::OrientedBox{{1.0, 0, 0}, {0.1, 2, 2}, Eigen::Matrix3d::Identity()}, 2, {90, 90, 90},
             synthetic::Texture::kNoise});
  volume::VolumeParams p;
  volume::LabeledVolume volume(p);
  testing::fuse(volume, scene, {synthetic::lookAt({0, 0, 0}, {1, 0, 0})});
  const LabeledMesh m = extractMesh(volume).value();
  ASSERT_GT(m.vertices.size(), 1000u);
  for (const auto& v : m.vertices) ASSERT_NEAR(v.x(), 0.9f, p.voxel_size);
}

}  // namespace
}  // namespace semfuse::render
