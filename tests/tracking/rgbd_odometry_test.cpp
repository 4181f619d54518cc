// Dense image alignment between two rendered views of the synthetic room with a known motion
// between them: the small images must recover it well inside the SDF alignment's basin, from no
// prior and from a keyframe's coarse images alone.
#include <gtest/gtest.h>

#include "semfuse/synthetic/room.hpp"
#include "semfuse/tracking/depth_pyramid.hpp"
#include "semfuse/tracking/image_pyramid.hpp"
#include "semfuse/tracking/rgbd_odometry.hpp"
#include "tracking_fixtures.hpp"

namespace semfuse::tracking::testing {
namespace {

ImagePyramid imagesOf(const synthetic::RenderedView& view) {
  DepthPyramid pyramid;
  EXPECT_TRUE(pyramid.build(view.depth, view.color, view.intrinsics, PyramidParams{}).ok());
  ImagePyramid images;
  images.build(pyramid);
  return images;
}

class RgbdOdometry : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { scene_ = new synthetic::LabeledScene(synthetic::makeRoom()); }
  static void TearDownTestSuite() { delete scene_; }

  // Current-from-reference motion the images must find when the camera moves by `offset`.
  static void expectRecovered(const RigidOffset& offset, bool keyframe_levels) {
    const Pose reference_pose = referencePose();
    const Pose current_pose = applyOffset(offset, reference_pose);
    ImagePyramid reference = imagesOf(renderOrDie(*scene_, reference_pose));
    if (keyframe_levels) reference.releaseFinerThan(1);
    const ImagePyramid current = imagesOf(renderOrDie(*scene_, current_pose));
    const OdometryResult result = alignImages(reference, current, Pose::Identity());
    const Pose estimated = reference_pose * result.current_from_reference.inverse();
    SCOPED_TRACE(::testing::Message() << offset.angle_deg << " deg, " << offset.translation_m.transpose() << " m"
                                      << (keyframe_levels ? ", keyframe levels" : ""));
    EXPECT_LT(translationError(estimated, current_pose), keyframe_levels ? 0.02 : 0.01);
    EXPECT_LT(rotationErrorDeg(estimated, current_pose), keyframe_levels ? 1.0 : 0.5);
    EXPECT_GT(result.matched_ratio, 0.8);  // where the two images overlap, they agree
  }

  static synthetic::LabeledScene* scene_;
};
synthetic::LabeledScene* RgbdOdometry::scene_ = nullptr;

TEST_F(RgbdOdometry, RecoversMotionBetweenConsecutiveFrames) {
  for (const RigidOffset& offset : std::vector<RigidOffset>{{Eigen::Vector3d::UnitZ(), 2.0, {0.02, -0.01, 0.0}},
                                                            {Eigen::Vector3d::UnitX(), -4.0, {0.0, 0.03, 0.02}},
                                                            {Eigen::Vector3d(1, 1, 0), 6.0, {0.05, 0.0, -0.03}}})
    expectRecovered(offset, false);
}

TEST_F(RgbdOdometry, RecoversMotionFromAKeyframesCoarseImages) {
  for (const RigidOffset& offset : std::vector<RigidOffset>{{Eigen::Vector3d::UnitZ(), 5.0, {0.10, 0.0, 0.0}},
                                                            {Eigen::Vector3d(0, 1, 1), 8.0, {0.0, 0.08, 0.05}}})
    expectRecovered(offset, true);
}

TEST_F(RgbdOdometry, ImagesThatShareNothingMatchNothing) {
  const Pose reference_pose = referencePose();
  Pose elsewhere = reference_pose;
  elsewhere.linear() = reference_pose.linear() * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const OdometryResult result = alignImages(imagesOf(renderOrDie(*scene_, reference_pose)),
                                            imagesOf(renderOrDie(*scene_, elsewhere)), Pose::Identity());
  EXPECT_LT(result.overlap * result.matched_ratio, 0.3);
}

}  // namespace
}  // namespace semfuse::tracking::testing
