// Depth integration against analytic geometry: the fused zero crossing must sit within half a
// voxel of the true surface, invalid depth must change nothing, bad input must be refused.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

#include "analytic_scene.hpp"
#include "semfuse/volume/integrator.hpp"
#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::volume {
namespace {
using testing::lookAt;
using testing::smallCamera;

// Signed distance along `normal` from `point` to the fused zero crossing (bisection on the
// interpolated TSDF within +-2 voxels); NaN where the TSDF is unobserved or does not cross.
double zeroCrossingOffset(VolumeSampler& sampler, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                          double voxel) {
  double lo = -2 * voxel, hi = 2 * voxel;
  float f_lo = 0, f_hi = 0;
  if (!sampler.tsdf(Eigen::Vector3d(point + lo * normal), f_lo) ||
      !sampler.tsdf(Eigen::Vector3d(point + hi * normal), f_hi))
    return std::numeric_limits<double>::quiet_NaN();
  if (!(f_lo < 0 && f_hi > 0)) return std::numeric_limits<double>::quiet_NaN();
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    float f = 0;
    if (!sampler.tsdf(Eigen::Vector3d(point + mid * normal), f)) return std::numeric_limits<double>::quiet_NaN();
    (f < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(IntegrateGeometry, PlaneZeroCrossingWithinHalfAVoxel) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  const Eigen::Vector3d n(0, 0, -1);  // the plane z = 1.2 faces the cameras at z < 1.2
  const double offset = -1.2;
  const Eigen::Vector3d target(0.05, -0.03, 1.2);
  const std::vector<Eigen::Vector3d> eyes = {{0, 0, 0}, {0.3, 0.1, 0.1}, {-0.25, -0.2, 0.05}, {0.1, -0.3, 0.2}};
  for (const auto& eye : eyes) {
    const Pose pose = lookAt(eye, target);
    auto stats = integrate(volume, testing::renderPlane(k, pose, n, offset), cv::Mat(), k, pose);
    ASSERT_TRUE(stats.ok()) << stats.error();
    EXPECT_GT(stats.value().voxels_updated, 10000u);
  }
  EXPECT_EQ(volume.framesIntegrated(), eyes.size());

  VolumeSampler sampler(volume);
  const double voxel = volume.voxelSize();
  int checked = 0;
  for (double x = -0.2; x <= 0.2; x += 0.037)
    for (double y = -0.15; y <= 0.15; y += 0.041) {
      const Eigen::Vector3d on_plane(x, y, 1.2);
      const double off = zeroCrossingOffset(sampler, on_plane, n, voxel);
      ASSERT_FALSE(std::isnan(off)) << "no crossing at " << on_plane.transpose();
      EXPECT_LT(std::abs(off), 0.5 * voxel) << "at " << on_plane.transpose();
      float tsdf = 0;
      Eigen::Vector3f gradient;
      ASSERT_TRUE(sampler.tsdfAndGradient(on_plane, tsdf, gradient));
      EXPECT_GT(gradient.normalized().dot(Eigen::Vector3f(0, 0, -1)), 0.95f);  // points to free space
      ++checked;
    }
  EXPECT_GT(checked, 50);
}

TEST(IntegrateGeometry, SphereZeroCrossingWithinHalfAVoxel) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  const Eigen::Vector3d centre(0.1, 0.0, 1.5);
  const double radius = 0.25;
  const std::vector<Eigen::Vector3d> eyes = {{0, 0, 0.5}, {0.4, 0.0, 0.6}, {-0.3, 0.2, 0.6}, {0.1, -0.35, 0.55}};
  for (const auto& eye : eyes) {
    const Pose pose = lookAt(eye, centre);
    ASSERT_TRUE(integrate(volume, testing::renderSphere(k, pose, centre, radius), cv::Mat(), k, pose).ok());
  }
  VolumeSampler sampler(volume);
  const double voxel = volume.voxelSize();
  int checked = 0;
  // Points on the cap facing the cameras (all within 45 degrees of -z from the centre).
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j) {
      const Eigen::Vector3d normal = Eigen::Vector3d(0.15 * i, 0.15 * j, -1).normalized();
      const Eigen::Vector3d on_sphere = centre + radius * normal;
      const double off = zeroCrossingOffset(sampler, on_sphere, normal, voxel);
      ASSERT_FALSE(std::isnan(off)) << "no crossing at " << on_sphere.transpose();
      EXPECT_LT(std::abs(off), 0.5 * voxel) << "at " << on_sphere.transpose();
      ++checked;
    }
  EXPECT_EQ(checked, 81);
  // Inside the sphere, far behind the surface, nothing was observed.
  float tsdf = 0;
  EXPECT_FALSE(sampler.tsdf(centre, tsdf));
}

TEST(IntegrateGeometry, WeightIsClampedAndColourAveraged) {
  VolumeParams params;
  params.max_weight = 3;
  LabeledVolume volume(params);
  const PinholeIntrinsics k = smallCamera();
  const Pose pose = Pose::Identity();
  const cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  for (const cv::Scalar& rgb : {cv::Scalar(100, 0, 0), cv::Scalar(200, 0, 0), cv::Scalar(0, 90, 30)}) {
    const cv::Mat color(k.height, k.width, CV_8UC3, rgb);
    ASSERT_TRUE(integrate(volume, depth, color, k, pose).ok());
  }
  const openvdb::Coord on_surface(0, 0, 100);
  const VoxelValue v = volume.voxel(on_surface);
  EXPECT_EQ(v.weight, 3.0f);
  EXPECT_NEAR(v.tsdf, 0.0f, 1e-4f);
  EXPECT_EQ(volume.color(on_surface), (Rgb8{100, 30, 10}));  // (100 + 200 + 0) / 3, (0 + 0 + 90) / 3, 30 / 3

  // A fourth frame with the surface 1 cm closer (a full-weight observation, one voxel behind it):
  // weight stays at the clamp, average moves by 1/4.
  const cv::Mat closer(k.height, k.width, CV_32FC1, cv::Scalar(0.99));
  ASSERT_TRUE(integrate(volume, closer, cv::Mat(), k, pose).ok());
  EXPECT_EQ(volume.voxel(on_surface).weight, 3.0f);
  EXPECT_NEAR(volume.voxel(on_surface).tsdf, -0.01f / 4, 1e-4f);
}

// 1 cm voxels, 4 cm truncation: an observation weighs 1 down to 3 cm behind the surface, then
// less, linearly, to 1/16 at the truncation.
TEST(IntegrateGeometry, ObservationsFarBehindTheSurfaceWeighLess) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  const cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  ASSERT_TRUE(integrate(volume, depth, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_EQ(volume.voxel({0, 0, 98}).weight, 1.0f);                    // in front
  EXPECT_EQ(volume.voxel({0, 0, 100}).weight, 1.0f);                   // on the surface
  EXPECT_EQ(volume.voxel({0, 0, 102}).weight, 1.0f);                   // 2 cm behind
  EXPECT_NEAR(volume.voxel({0, 0, 104}).weight, 1.0f / 16.0f, 1e-3f);  // at the truncation
  EXPECT_NEAR(volume.voxel({0, 0, 104}).tsdf, -0.04f, 1e-4f);          // one view: its value, whatever its weight

  // The surface 5 cm farther: voxel 104, at the truncation behind the first surface, lies 1 cm in
  // front of this one, and the view that sees it in front outweighs the one that saw it behind:
  // (-0.04 / 16 + 0.01) / (1/16 + 1) = 0.00706 (-0.015 at equal weights).
  const cv::Mat farther(k.height, k.width, CV_32FC1, cv::Scalar(1.05));
  ASSERT_TRUE(integrate(volume, farther, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_NEAR(volume.voxel({0, 0, 104}).tsdf, 0.0075f / 1.0625f, 1e-4f);
  EXPECT_NEAR(volume.voxel({0, 0, 104}).weight, 1.0625f, 1e-3f);

  // Halfway through the drop (3.5 cm behind), half the weight.
  LabeledVolume halfway;
  const cv::Mat nearer(k.height, k.width, CV_32FC1, cv::Scalar(0.995));
  ASSERT_TRUE(integrate(halfway, nearer, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_NEAR(halfway.voxel({0, 0, 103}).weight, 0.5f, 2e-3f);
}

// weight_dropoff 1: every observation weighs 1 down to the truncation (KinectFusion's weight); 0.5:
// the drop starts 2 cm behind a 4 cm truncation, and 3 cm behind is halfway through it.
TEST(IntegrateGeometry, TheWeightDropOffIsAParameter) {
  const PinholeIntrinsics k = smallCamera();
  const cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  VolumeParams constant;
  constant.weight_dropoff = 1.0f;
  LabeledVolume flat(constant);
  ASSERT_TRUE(integrate(flat, depth, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_EQ(flat.voxel({0, 0, 103}).weight, 1.0f);
  EXPECT_EQ(flat.voxel({0, 0, 104}).weight, 1.0f);  // at the truncation

  VolumeParams early;
  early.weight_dropoff = 0.5f;
  LabeledVolume dropping(early);
  ASSERT_TRUE(integrate(dropping, depth, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_EQ(dropping.voxel({0, 0, 102}).weight, 1.0f);           // 2 cm behind: where the drop starts
  EXPECT_NEAR(dropping.voxel({0, 0, 103}).weight, 0.5f, 2e-3f);  // halfway through the drop
  EXPECT_NEAR(dropping.voxel({0, 0, 104}).weight, 1.0f / 16.0f, 1e-3f);
}

TEST(IntegrateGeometry, TsdfIsTruncatedAndNotUpdatedFarBehind) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  const cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  ASSERT_TRUE(integrate(volume, depth, cv::Mat(), k, Pose::Identity()).ok());
  EXPECT_NEAR(volume.voxel({0, 0, 98}).tsdf, 0.02f, 1e-5f);
  EXPECT_NEAR(volume.voxel({0, 0, 97}).tsdf, 0.03f, 1e-5f);
  EXPECT_NEAR(volume.voxel({0, 0, 102}).tsdf, -0.02f, 1e-5f);
  EXPECT_NEAR(volume.voxel({0, 0, 104}).tsdf, -0.04f, 1e-5f);
  EXPECT_FALSE(volume.voxel({0, 0, 105}).observed());  // 5 cm behind: beyond the truncation
  // Free space in front of the band, in an allocated leaf, is clamped at +truncation.
  const VoxelValue front = volume.voxel({0, 0, 95});
  if (front.observed()) {
    EXPECT_NEAR(front.tsdf, 0.04f, 1e-5f);
  }
}

TEST(IntegrateGeometry, InvalidDepthChangesNothing) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  // Left third: zero; middle: NaN; right: 65.535 m (7-Scenes' 0xFFFF), beyond max_depth.
  depth.colRange(0, 53).setTo(0.0f);
  depth.colRange(53, 106).setTo(std::numeric_limits<float>::quiet_NaN());
  depth.colRange(106, 160).setTo(65.535f);
  depth.rowRange(0, 10).setTo(1.0f);  // a valid strip along the top keeps the frame non-empty
  auto stats = integrate(volume, depth, cv::Mat(), k, Pose::Identity());
  ASSERT_TRUE(stats.ok()) << stats.error();
  EXPECT_EQ(stats.value().valid_pixels, 10u * 160u);
  // Voxels straight ahead (image centre) project into invalid pixels: untouched.
  for (int z = 90; z <= 110; ++z) EXPECT_FALSE(volume.voxel({0, 0, z}).observed()) << z;
  EXPECT_FALSE(volume.voxel({-40, 0, 100}).observed());
  EXPECT_FALSE(volume.voxel({40, 0, 100}).observed());
  // The valid strip (rows 0-9, y = (v - 59.5) / 150 m at 1 m) is observed.
  EXPECT_TRUE(volume.voxel({0, -37, 100}).observed());
}

TEST(IntegrateGeometry, RefusesBadInputWithAPreciseMessage) {
  LabeledVolume volume;
  const PinholeIntrinsics k = smallCamera();
  const cv::Mat depth(k.height, k.width, CV_32FC1, cv::Scalar(1.0));
  const Pose pose = Pose::Identity();
  auto expectError = [&](const Result<IntegrationStats>& r, const std::string& fragment) {
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().find(fragment), std::string::npos) << r.error();
  };
  expectError(integrate(volume, cv::Mat(k.height, k.width, CV_16UC1), cv::Mat(), k, pose), "depth: expected CV_32FC1");
  expectError(integrate(volume, cv::Mat(), cv::Mat(), k, pose), "depth: image is empty");
  expectError(integrate(volume, cv::Mat(100, 100, CV_32FC1, 1.0f), cv::Mat(), k, pose), "differs from the intrinsics");
  expectError(integrate(volume, depth, cv::Mat(10, 10, CV_8UC3), k, pose), "color: size");
  expectError(integrate(volume, depth, cv::Mat(k.height, k.width, CV_8UC1), k, pose), "color: expected CV_8UC3");
  PinholeIntrinsics bad_k = k;
  bad_k.fx = 0;
  expectError(integrate(volume, depth, cv::Mat(), bad_k, pose), "focal lengths");
  bad_k = k;
  bad_k.cy = std::nan("");
  expectError(integrate(volume, depth, cv::Mat(), bad_k, pose), "principal point");
  Pose nan_pose = pose;
  nan_pose.translation().x() = std::nan("");
  expectError(integrate(volume, depth, cv::Mat(), k, nan_pose), "pose: non-finite value nan at row 0, column 3");
  Pose skewed = pose;
  skewed.linear()(0, 1) = 0.3;
  expectError(integrate(volume, depth, cv::Mat(), k, skewed), "pose: rotation is not orthonormal");
  Pose mirrored = pose;
  mirrored.linear()(0, 0) = -1;
  expectError(integrate(volume, depth, cv::Mat(), k, mirrored), "pose: rotation is a reflection");
  const cv::Mat labels(k.height, k.width, CV_16UC1, cv::Scalar(1));
  expectError(integrate(volume, depth, cv::Mat(), cv::Mat(200, 200, CV_16UC1), cv::Mat(), k, pose),
              "larger than the depth");
  expectError(integrate(volume, depth, cv::Mat(), cv::Mat(k.height, k.width, CV_8UC1), cv::Mat(), k, pose),
              "labels: expected CV_16UC1");
  expectError(integrate(volume, depth, cv::Mat(), labels, cv::Mat(5, 5, CV_32FC1), k, pose), "confidence: size");
  expectError(integrate(volume, depth, cv::Mat(), labels, cv::Mat(k.height, k.width, CV_8UC1), k, pose),
              "confidence: expected CV_32FC1");
  expectError(integrate(volume, depth, cv::Mat(), cv::Mat(), cv::Mat(k.height, k.width, CV_32FC1), k, pose),
              "without labels");
  expectError(integrateLabels(volume, depth, cv::Mat(), cv::Mat(), k, pose), "labels: image is empty");
  Frame frame;
  frame.depth = depth;
  frame.intrinsics = k;
  expectError(integrate(volume, frame), "carries no camera_to_world pose");
  // Nothing of the refused frames reached the volume.
  EXPECT_EQ(volume.allocatedLeaves(), 0u);
  EXPECT_EQ(volume.framesIntegrated(), 0u);
}

TEST(VolumeMemory, GeometryAndLabelsTakeEightBytesPerVoxelPlusTreeOverhead) {
  VolumeParams params;
  params.integrate_color = false;
  LabeledVolume volume(params);
  const PinholeIntrinsics k = smallCamera();
  const Pose pose = lookAt({0, 0, 0}, {0, 0, 1});
  ASSERT_TRUE(integrate(volume, testing::renderPlane(k, pose, {0, 0, -1}, -1.0), cv::Mat(), k, pose).ok());
  ASSERT_GT(volume.allocatedLeaves(), 50u);
  const double leaf_payload = sizeof(GeometryGrid::TreeType::LeafNodeType::ValueType);
  std::size_t leaf_bytes = 0;
  for (auto leaf = volume.geometryGrid().tree().cbeginLeaf(); leaf; ++leaf) leaf_bytes += leaf->memUsage();
  const double leaf_per_voxel = static_cast<double>(leaf_bytes) / volume.allocatedVoxels();
  const double total_per_voxel = static_cast<double>(volume.geometryMemoryBytes()) / volume.allocatedVoxels();
  ::testing::Test::RecordProperty("leaf_bytes_per_allocated_voxel", std::to_string(leaf_per_voxel));
  std::printf(
      "geometry+label layer: %.3f bytes per allocated voxel in leaves, %.3f with the internal nodes of "
      "this small map (%zu leaves, %zu observed voxels)\n",
      leaf_per_voxel, total_per_voxel, volume.allocatedLeaves(), volume.observedVoxels());
  EXPECT_EQ(leaf_payload, 8.0);
  // 8 bytes of payload plus the leaf's active mask (1 bit) and header: under 3% overhead. The
  // internal nodes are a fixed cost per 4096 leaves, large here, small in a real map (bench).
  EXPECT_LE(leaf_per_voxel, 8.0 * 1.03);
  EXPECT_GT(volume.observedVoxels(), volume.allocatedVoxels() / 4);
}

}  // namespace
}  // namespace semfuse::volume
