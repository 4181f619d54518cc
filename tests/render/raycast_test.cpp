// Raycast depth, normals and labels of fused analytic surfaces against their exact renderings.
#include <cmath>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "dense_crossing.hpp"
#include "fused_scene.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/synthetic/room.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::render {
namespace {

using synthetic::LabeledScene;

using testing::kVoxel;

// A floor slab (top at z = 0) and a sphere resting above it, each with its own label.
LabeledScene planeAndSphere() {
  LabeledScene scene;
  scene.add({"plane",
             synthetic::OrientedBox{{0, 0, -0.1}, {1.5, 1.5, 0.1}, Eigen::Matrix3d::Identity()},
             1,
             {200, 180, 150},
             synthetic::Texture::kChecker});
  scene.add({"sphere", synthetic::Sphere{{0.1, 0.05, 0.35}, 0.3}, 7, {200, 40, 40}, synthetic::Texture::kNoise});
  return scene;
}

struct DepthComparison {
  double mean_abs_error = 0.0;
  int compared = 0;
  int truth_pixels = 0;
};

DepthComparison compareDepth(const cv::Mat& raycast, const cv::Mat& truth) {
  DepthComparison c;
  double sum = 0.0;
  for (int v = 0; v < truth.rows; ++v)
    for (int u = 0; u < truth.cols; ++u) {
      const float t = truth.at<float>(v, u), r = raycast.at<float>(v, u);
      if (t > 0) ++c.truth_pixels;
      if (t > 0 && r > 0) {
        sum += std::abs(t - r);
        ++c.compared;
      }
    }
  c.mean_abs_error = c.compared ? sum / c.compared : 1e9;
  return c;
}

class RaycastTest : public ::testing::Test {
 protected:
  void SetUp() override { testing::fuse(volume_, scene_, testing::arcAround({0.1, 0.05, 0.2}, 1.2, 0.7, 6)); }

  LabeledScene scene_ = planeAndSphere();
  volume::LabeledVolume volume_{testing::fusedVolumeParams()};
  // A view between the integrated ones.
  Pose novel_ = synthetic::lookAt({-1.0, 0.3, 0.8}, {0.1, 0.0, 0.25});
};

TEST_F(RaycastTest, DepthMatchesAnalyticDepthWithinHalfAVoxel) {
  const auto images = raycast(volume_, testing::kSmallCamera, novel_, {kAllLayers});
  ASSERT_TRUE(images.ok()) << images.error();
  const auto truth = synthetic::renderView(scene_, testing::kSmallCamera, novel_).value();
  const DepthComparison c = compareDepth(images.value().depth, truth.depth);
  EXPECT_LT(c.mean_abs_error, 0.5 * kVoxel);
  EXPECT_GT(c.compared, 0.9 * c.truth_pixels);  // and the surface is actually found
  RecordProperty("mean_abs_depth_error_mm", std::to_string(c.mean_abs_error * 1000));
}

TEST_F(RaycastTest, NormalsAndLabelsMatchTheSurfaceHit) {
  const auto images = raycast(volume_, testing::kSmallCamera, novel_, {kAllLayers}).value();
  const auto truth = synthetic::renderView(scene_, testing::kSmallCamera, novel_).value();
  int compared = 0, normals_agree = 0, labels_agree = 0, with_evidence = 0;
  for (int v = 0; v < truth.depth.rows; ++v)
    for (int u = 0; u < truth.depth.cols; ++u) {
      if (images.depth.at<float>(v, u) <= 0 || truth.depth.at<float>(v, u) <= 0) continue;
      ++compared;
      const cv::Vec3f a = images.normals.at<cv::Vec3f>(v, u), b = truth.normals.at<cv::Vec3f>(v, u);
      normals_agree += a.dot(b) > std::cos(10.0 * M_PI / 180) ? 1 : 0;
      labels_agree += images.labels.at<uint16_t>(v, u) == truth.labels.at<uint16_t>(v, u) ? 1 : 0;
      with_evidence += images.scores.at<float>(v, u) > 0.0f ? 1 : 0;
    }
  ASSERT_GT(compared, 1000);
  // Gradients of a projective TSDF bend where the sphere was only seen at grazing angles (its rim);
  // everywhere else they follow the surface.
  EXPECT_GT(normals_agree, 0.85 * compared);
  EXPECT_GT(labels_agree, 0.98 * compared);
  EXPECT_GT(with_evidence, 0.95 * compared);
}

// The fast path against the plain march: where the two disagree (rarely), the brute-force
// crossing decides, and the fast path must be the one that found it.
struct Disagreement {
  int hit = 0;          // pixels where either found a surface
  int differ = 0;       // of those, where they differ by a tenth of a voxel or more
  int fast_right = 0;   // of those, where the fast path matches the brute-force crossing
  int plain_right = 0;  // ... and where the plain march does
};

Disagreement judgeDisagreements(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& pose,
                                const RaycastOptions& options, const cv::Mat& fast, const cv::Mat& plain) {
  Disagreement d;
  auto same = [](double a, double b) { return (a <= 0 && b <= 0) || std::abs(a - b) < 0.1 * kVoxel; };
  for (int v = 0; v < fast.rows; ++v)
    for (int u = 0; u < fast.cols; ++u) {
      const float a = fast.at<float>(v, u), b = plain.at<float>(v, u);
      if (a <= 0 && b <= 0) continue;
      ++d.hit;
      if (same(a, b)) continue;
      ++d.differ;
      const double truth = testing::denseFirstCrossing(volume, k, pose, u, v, options);
      d.fast_right += same(a, truth) ? 1 : 0;
      d.plain_right += same(b, truth) ? 1 : 0;
    }
  return d;
}

// The fast path and the plain march see the same surface (both found it, within a tenth of a
// voxel, on >= 98.5 % of the pixels either hit), and where they differ the fast path found the
// brute-force crossing (the plain march steps over crossings that graze a cell between two of
// its samples and misses those right behind the boundary of observed space; the fast path misses
// only where the ray touches the zero level tangentially).
void expectFastPathRightWhereTheyDiffer(const volume::LabeledVolume& volume, const PinholeIntrinsics& k,
                                        const Pose& pose, const RaycastOptions& options, const cv::Mat& fast,
                                        const cv::Mat& plain) {
  const Disagreement d = judgeDisagreements(volume, k, pose, options, fast, plain);
  ASSERT_GT(d.hit, 1000);
  EXPECT_LT(d.differ, 0.015 * d.hit);
  EXPECT_GE(d.fast_right, 0.97 * d.differ) << d.fast_right << " of " << d.differ << " disagreements";
  ::testing::Test::RecordProperty("disagreements", d.differ);
  ::testing::Test::RecordProperty("fast_path_right", d.fast_right);
  ::testing::Test::RecordProperty("plain_march_right", d.plain_right);
}

TEST_F(RaycastTest, EmptySpaceSkippingFindsTheSameSurface) {
  RaycastOptions skip{kDepthLayer | kLabelsLayer};
  RaycastOptions march = skip;
  march.skip_empty_space = false;
  const auto a = raycast(volume_, testing::kSmallCamera, novel_, skip).value();
  const auto b = raycast(volume_, testing::kSmallCamera, novel_, march).value();
  // Samples fall at other places along the ray, so the crossing may move by a hair; a ray that
  // grazes a thin band may find it in one march and not the other, but only rarely.
  expectFastPathRightWhereTheyDiffer(volume_, testing::kSmallCamera, novel_, skip, a.depth, b.depth);
}

// A camera inside the sphere's band (2 cm off its surface) looking down at the floor: blocks of
// surface cells reach behind its image plane, so the per-pixel depth bounds cannot project them
// and must open every pixel from the near clip on. Rays must still find the surface.
TEST_F(RaycastTest, SkippingFromInsideTheMapFindsTheSameSurface) {
  const Pose inside = synthetic::lookAt({-0.22, 0.05, 0.35}, {-0.5, 0.05, 0.0});
  RaycastOptions skip{kDepthLayer};
  skip.min_depth = 0.01;
  RaycastOptions march = skip;
  march.skip_empty_space = false;
  const auto a = raycast(volume_, testing::kSmallCamera, inside, skip).value();
  const auto b = raycast(volume_, testing::kSmallCamera, inside, march).value();
  expectFastPathRightWhereTheyDiffer(volume_, testing::kSmallCamera, inside, skip, a.depth, b.depth);
}

// The synthetic room (walls, furniture, thin chair legs, objects in front of others) from a view
// between the fused ones: rays started at the per-pixel surface bounds must find the surface the
// plain march finds, with the same labels, and the right one where the two differ.
TEST(RaycastRoom, SkippingFindsTheSameSurfaceAndLabelsAsThePlainMarch) {
  const LabeledScene room = synthetic::makeRoom();
  volume::LabeledVolume fused{testing::fusedVolumeParams()};
  testing::fuse(fused, room, testing::arcAround({0.0, 0.0, 0.7}, 1.8, 0.6, 8, 2.5));
  const PinholeIntrinsics camera = testing::kSmallCamera.scaled(0.5);  // the plain march is slow
  const Pose view = synthetic::lookAt({-1.2, 0.8, 1.4}, {0.4, -0.3, 0.5});
  RaycastOptions skip{kDepthLayer | kLabelsLayer};
  RaycastOptions march = skip;
  march.skip_empty_space = false;
  const auto a = raycast(fused, camera, view, skip).value();
  const auto b = raycast(fused, camera, view, march).value();
  expectFastPathRightWhereTheyDiffer(fused, camera, view, skip, a.depth, b.depth);
  int same_depth = 0, same_label = 0;
  for (int v = 0; v < a.depth.rows; ++v)
    for (int u = 0; u < a.depth.cols; ++u) {
      const float da = a.depth.at<float>(v, u), db = b.depth.at<float>(v, u);
      if (da <= 0 || std::abs(da - db) >= 0.1 * kVoxel) continue;
      ++same_depth;
      same_label += a.labels.at<uint16_t>(v, u) == b.labels.at<uint16_t>(v, u) ? 1 : 0;
    }
  EXPECT_GT(same_label, 0.995 * same_depth);
}

// The portable and the AVX2 voxel readers (RaycastKernel) must render the same images bit for
// bit: on a fused room, and on the same room with its TSDF halves replaced by a scramble of every
// finite bit pattern (subnormals, +-0, the largest halves) and some weights zeroed.
TEST(RaycastRoom, KernelsGiveBitIdenticalImages) {
  if (!raycastKernelAvailable(RaycastKernel::kAvx2)) GTEST_SKIP() << "this CPU has no AVX2 + F16C";
  const LabeledScene room = synthetic::makeRoom();
  volume::LabeledVolume fused{testing::fusedVolumeParams()};
  testing::fuse(fused, room, testing::arcAround({0.0, 0.0, 0.7}, 1.8, 0.6, 8, 2.5));
  const Pose view = synthetic::lookAt({-1.2, 0.8, 1.4}, {0.4, -0.3, 0.5});
  const RaycastOptions all{kAllLayers};
  auto render = [&](RaycastKernel kernel) {
    EXPECT_TRUE(setRaycastKernel(kernel));
    auto images = raycast(fused, testing::kSmallCamera, view, all);
    setRaycastKernel(RaycastKernel::kAvx2);
    return std::move(images).value();
  };
  auto expectSame = [](const RaycastImages& a, const RaycastImages& b) {
    for (const auto& [x, y] : {std::pair{a.depth, b.depth},
                               {a.normals, b.normals},
                               {a.labels, b.labels},
                               {a.scores, b.scores},
                               {a.color, b.color}}) {
      ASSERT_EQ(x.size(), y.size());
      EXPECT_EQ(0, std::memcmp(x.data, y.data, x.total() * x.elemSize()));
    }
  };
  const RaycastImages fused_scalar = render(RaycastKernel::kScalar);
  expectSame(fused_scalar, render(RaycastKernel::kAvx2));
  EXPECT_GT(cv::countNonZero(fused_scalar.depth), testing::kSmallCamera.width * testing::kSmallCamera.height / 2);

  uint32_t scramble = 0;
  for (auto voxel = fused.mutableGeometryGrid().beginValueOn(); voxel; ++voxel) {
    uint64_t bits = static_cast<uint64_t>(*voxel);
    scramble += 0x9E37u;
    uint32_t half = scramble & 0xFFFFu;
    if ((half & 0x7C00u) == 0x7C00u) half &= ~0x4000u;  // no inf or NaN: the map holds none
    bits = (bits & ~uint64_t{0xFFFF}) | half;
    if (scramble % 7 == 0) bits &= ~uint64_t{0xFFFF0000};  // unobserved
    voxel.setValue(static_cast<volume::PackedVoxel>(bits));
  }
  const RaycastImages scrambled = render(RaycastKernel::kScalar);
  expectSame(scrambled, render(RaycastKernel::kAvx2));
  EXPECT_GT(cv::countNonZero(scrambled.depth), 1000);
}

TEST_F(RaycastTest, AnyResolutionOnlyRequestedLayers) {
  const auto small = raycast(volume_, testing::kSmallCamera.scaled(0.25), novel_, {kDepthLayer}).value();
  EXPECT_EQ(small.depth.cols, 80);
  EXPECT_EQ(small.depth.rows, 60);
  EXPECT_TRUE(small.normals.empty());
  EXPECT_TRUE(small.labels.empty());
  EXPECT_GT(cv::countNonZero(small.depth), 80 * 60 / 4);
}

TEST_F(RaycastTest, SaveLoadRaycastIsBitIdentical) {
  // Geometry and labels only: with colour, loadMap currently rejects the file ("colour grid's
  // topology differs"), an open semfuse::volume issue; add kColorLayer here once it is fixed.
  volume::VolumeParams no_color = testing::fusedVolumeParams();
  no_color.integrate_color = false;
  volume::LabeledVolume fused{no_color};
  testing::fuse(fused, scene_, testing::arcAround({0.1, 0.05, 0.2}, 1.2, 0.7, 6));
  const auto path =
      std::filesystem::temp_directory_path() / ("semfuse_render_roundtrip_" + std::to_string(::getpid()) + ".vdb");
  const Status saved = volume::saveMap(fused, LabelLegend{}, path);
  ASSERT_TRUE(saved.ok()) << saved.error();
  auto loaded = volume::loadMap(path);
  std::filesystem::remove(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const RaycastOptions layers{kDepthLayer | kNormalsLayer | kLabelsLayer | kConfidenceLayer};
  const auto a = raycast(fused, testing::kSmallCamera, novel_, layers).value();
  const auto b = raycast(loaded.value().volume, testing::kSmallCamera, novel_, layers).value();
  for (const auto& [x, y] :
       {std::pair{a.depth, b.depth}, {a.normals, b.normals}, {a.labels, b.labels}, {a.scores, b.scores}}) {
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(0, std::memcmp(x.data, y.data, x.total() * x.elemSize()));
  }
  EXPECT_GT(cv::countNonZero(a.depth), 1000);
}

// The server's way: copy what the rays read under its lock, render later. The images are those
// of a direct raycast at the time of the copy, bit for bit, whatever happens to the volume after.
TEST_F(RaycastTest, PreparedRaycastRendersTheVolumeAsItWasWhenPrepared) {
  const RaycastOptions all{kAllLayers};
  const auto direct = raycast(volume_, testing::kSmallCamera, novel_, all).value();
  auto prepared = prepareRaycast(volume_, testing::kSmallCamera, novel_, all);
  ASSERT_TRUE(prepared.ok()) << prepared.error();
  volume_.clear();  // the map moves on (here: is reset) before the copy is rendered
  const auto later = raycast(std::move(prepared.value()));
  ASSERT_TRUE(later.ok()) << later.error();
  const RaycastImages& b = later.value();
  for (const auto& [x, y] : {std::pair{direct.depth, b.depth},
                             {direct.normals, b.normals},
                             {direct.labels, b.labels},
                             {direct.scores, b.scores},
                             {direct.color, b.color}}) {
    ASSERT_EQ(x.size(), y.size());
    EXPECT_EQ(0, std::memcmp(x.data, y.data, x.total() * x.elemSize()));
  }
  EXPECT_GT(cv::countNonZero(direct.depth), 1000);
  EXPECT_GT(cv::countNonZero(direct.color.reshape(1)), 1000);  // the colour layer is there too
  // A prepared raycast renders once.
  EXPECT_FALSE(raycast(std::move(prepared.value())).ok());
}

// Bad requests fail at prepareRaycast with the same reasons as raycast.
TEST_F(RaycastTest, PrepareRejectsWhatRaycastRejects) {
  RaycastOptions none{0};
  EXPECT_FALSE(prepareRaycast(volume_, testing::kSmallCamera, novel_, none).ok());
  Pose not_rigid = novel_;
  not_rigid.linear() *= 2.0;
  EXPECT_FALSE(prepareRaycast(volume_, testing::kSmallCamera, not_rigid, {}).ok());
}

// Rays parallel to grid axes and planes: a camera whose axes are the grid's, with its principal
// point on a pixel centre, sends that pixel's ray along a grid axis and the rays of its row and
// column in grid planes (zero direction components, where the walk's per-axis steps are
// infinite; a NaN there once made rays loop forever). The fast path must find what the plain
// march finds there, or the brute-force crossing where they differ: looking straight down at the
// floor, and horizontally at the sphere.
TEST_F(RaycastTest, RaysAlongGridAxesFindTheSameSurface) {
  const PinholeIntrinsics centred{320, 240, 262.5, 262.5, 160.0, 120.0};
  Pose down = Pose::Identity();
  down.linear() = Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();  // camera z = world -z
  down.translation() = Eigen::Vector3d(0.5, 0.5, 1.0);
  Pose level = Pose::Identity();  // camera z = world +x, camera y = world -z: row 120 is horizontal
  level.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  level.translation() = Eigen::Vector3d(-0.8, 0.05, 0.35);
  RaycastOptions fast{kDepthLayer | kNormalsLayer};
  RaycastOptions plain = fast;
  plain.skip_empty_space = false;
  for (const auto& [pose, centre_depth] : {std::pair{down, 1.0}, {level, 0.6}}) {
    const auto a = raycast(volume_, centred, pose, fast).value();
    const auto b = raycast(volume_, centred, pose, plain).value();
    EXPECT_NEAR(a.depth.at<float>(120, 160), centre_depth, 0.5 * kVoxel);
    // Row 120 and column 160: where fast and plain differ, the brute-force crossing decides.
    int hits = 0, differ = 0, fast_wrong = 0;
    auto compare = [&](int u, int v) {
      const float da = a.depth.at<float>(v, u), db = b.depth.at<float>(v, u);
      if (da <= 0 && db <= 0) return;
      ++hits;
      if (std::abs(da - db) < 0.1 * kVoxel) return;
      ++differ;
      const double truth = testing::denseFirstCrossing(volume_, centred, pose, u, v, fast);
      fast_wrong += (da <= 0 && truth <= 0) || std::abs(da - truth) < 0.1 * kVoxel ? 0 : 1;
    };
    for (int u = 0; u < centred.width; ++u) compare(u, 120);
    for (int v = 0; v < centred.height; ++v) compare(160, v);
    EXPECT_GT(hits, 250);
    EXPECT_LT(differ, 0.05 * hits);
    EXPECT_EQ(fast_wrong, 0) << "of " << differ << " pixels where fast and plain differ";
  }
}

TEST(Raycast, EmptyVolumeGivesEmptyImages) {
  const volume::LabeledVolume empty{testing::fusedVolumeParams()};
  const auto images = raycast(empty, testing::kSmallCamera, Pose::Identity()).value();
  EXPECT_EQ(cv::countNonZero(images.depth), 0);
}

TEST(Raycast, RejectsBadRequestsWithReasons) {
  volume::VolumeParams no_color = testing::fusedVolumeParams();
  no_color.integrate_color = false;
  const volume::LabeledVolume volume{no_color};
  auto expectError = [&](const PinholeIntrinsics& k, const Pose& pose, const RaycastOptions& o, const char* word) {
    const auto r = raycast(volume, k, pose, o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find(word), std::string::npos) << r.error();
  };
  PinholeIntrinsics zero = testing::kSmallCamera;
  zero.height = 0;
  expectError(zero, Pose::Identity(), {}, "size");
  PinholeIntrinsics negative = testing::kSmallCamera;
  negative.fy = -1;
  expectError(negative, Pose::Identity(), {}, "focal");
  Pose sheared = Pose::Identity();
  sheared.linear()(0, 1) = 0.3;
  expectError(testing::kSmallCamera, sheared, {}, "orthonormal");
  expectError(testing::kSmallCamera, Pose::Identity(), {0}, "layer");
  expectError(testing::kSmallCamera, Pose::Identity(), {kColorLayer}, "colour");
  RaycastOptions range;
  range.max_depth = 0.05;
  expectError(testing::kSmallCamera, Pose::Identity(), range, "depth range");
}

}  // namespace
}  // namespace semfuse::render
