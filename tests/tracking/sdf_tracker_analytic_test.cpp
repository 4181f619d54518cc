// The alignment mathematics on the exact distance field of the synthetic room (no voxels): from
// the offsets the tracker must handle, it has to land on the true pose to well under a millimetre.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "analytic_field.hpp"
#include "semfuse/synthetic/primitives.hpp"
#include "semfuse/tracking/sdf_tracker.hpp"
#include "tracking_fixtures.hpp"

namespace semfuse::tracking::testing {
namespace {

class AnalyticTracking : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new synthetic::LabeledScene(synthetic::makeRoom());
    view_ = new synthetic::RenderedView(renderOrDie(*scene_, referencePose()));
  }
  static void TearDownTestSuite() {
    delete view_;
    delete scene_;
  }
  static synthetic::LabeledScene* scene_;
  static synthetic::RenderedView* view_;
};
synthetic::LabeledScene* AnalyticTracking::scene_ = nullptr;
synthetic::RenderedView* AnalyticTracking::view_ = nullptr;

TEST_F(AnalyticTracking, RecoversKnownRigidOffsets) {
  // The basin of convergence of SDF alignment is about the truncation band: a point displaced
  // farther reads the flat +truncation (or nothing) and pulls nowhere. A 10 degree rotation
  // moves the far wall by ~0.4 m, so this test (like the volume test) uses a 0.1 m band.
  const AnalyticField field(*scene_, 0.1f, roomInterior());
  SdfTracker tracker;
  for (const RigidOffset& offset : offsetsToRecover()) {
    const Pose guess = applyOffset(offset, referencePose());
    Result<Alignment> aligned = tracker.align(view_->depth, view_->intrinsics, field, guess);
    ASSERT_TRUE(aligned.ok()) << aligned.error();
    const Alignment& a = aligned.value();
    SCOPED_TRACE(::testing::Message() << "offset " << offset.angle_deg << " deg, " << offset.translation_m.transpose()
                                      << " m; start error " << translationError(guess, referencePose()) << " m");
    EXPECT_TRUE(a.ok()) << toString(a.lost_reason);
    EXPECT_LT(translationError(a.pose, referencePose()), 0.5e-3);
    EXPECT_LT(rotationErrorDeg(a.pose, referencePose()), 0.05);
    EXPECT_GT(a.quality.inlier_ratio, 0.9);
    EXPECT_LT(a.quality.rms_residual_m, 1e-3);
  }
}

TEST_F(AnalyticTracking, StartingAtTheTruthStaysThere) {
  const AnalyticField field(*scene_, 0.04f, roomInterior());
  SdfTracker tracker;
  Result<Alignment> aligned = tracker.align(view_->depth, view_->intrinsics, field, referencePose());
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_TRUE(aligned.value().ok());
  EXPECT_LT(translationError(aligned.value().pose, referencePose()), 1e-4);
  EXPECT_LT(rotationErrorDeg(aligned.value().pose, referencePose()), 0.01);
}

TEST(AnalyticDegenerate, FeaturelessPlaneIsReportedInsteadOfDrifting) {
  // One large slab: seen from above, every direction within the plane (and the rotation about
  // its normal) leaves the distances unchanged.
  synthetic::LabeledScene scene;
  synthetic::OrientedBox slab;
  slab.center = Eigen::Vector3d(0.0, 0.0, -0.1);
  slab.half_extents = Eigen::Vector3d(20.0, 20.0, 0.1);
  scene.add({"floor", slab, 1});
  const Pose truth = synthetic::lookAt(Eigen::Vector3d(0.0, 0.0, 1.5), Eigen::Vector3d(0.3, 0.2, 0.0));
  const synthetic::RenderedView view = renderOrDie(scene, truth);
  const AnalyticField field(scene, 0.04f);
  SdfTracker tracker;
  Pose guess = truth;
  guess.translation() += Eigen::Vector3d(0.03, -0.02, 0.0);  // slide along the plane
  Result<Alignment> aligned = tracker.align(view.depth, view.intrinsics, field, guess);
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_EQ(aligned.value().lost_reason, LostReason::kDegenerate);
  EXPECT_LT(aligned.value().quality.hessian_rcond, 1e-6);
  // The unobservable in-plane offset must not have been "corrected" into something else.
  EXPECT_LT(translationError(aligned.value().pose, guess), 1e-3);
}

TEST_F(AnalyticTracking, AllInvalidDepthIsLostWithItsReason) {
  const AnalyticField field(*scene_, 0.04f, roomInterior());
  SdfTracker tracker;
  cv::Mat nan_depth(480, 640, CV_32FC1, cv::Scalar(std::numeric_limits<float>::quiet_NaN()));
  Result<Alignment> aligned = tracker.align(nan_depth, kinectIntrinsics(), field, referencePose());
  ASSERT_TRUE(aligned.ok()) << aligned.error();
  EXPECT_EQ(aligned.value().lost_reason, LostReason::kNoValidDepth);
  EXPECT_TRUE(aligned.value().pose.isApprox(referencePose()));

  Result<Alignment> zeros =
      tracker.align(cv::Mat::zeros(480, 640, CV_32FC1), kinectIntrinsics(), field, referencePose());
  ASSERT_TRUE(zeros.ok());
  EXPECT_EQ(zeros.value().lost_reason, LostReason::kNoValidDepth);
}

TEST_F(AnalyticTracking, MalformedInputIsAnErrorNotACrash) {
  const AnalyticField field(*scene_, 0.04f, roomInterior());
  SdfTracker tracker;
  Result<Alignment> empty = tracker.align(cv::Mat(), kinectIntrinsics(), field, referencePose());
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.error().find("empty"), std::string::npos);

  Pose nan_pose = referencePose();
  nan_pose.translation().x() = std::numeric_limits<double>::quiet_NaN();
  Result<Alignment> bad_pose = tracker.align(view_->depth, view_->intrinsics, field, nan_pose);
  ASSERT_FALSE(bad_pose.ok());
  EXPECT_NE(bad_pose.error().find("not finite"), std::string::npos);

  TrackerParams params;
  params.robust_scale = -1.0f;
  SdfTracker misconfigured(params);
  Result<Alignment> bad_params = misconfigured.align(view_->depth, view_->intrinsics, field, referencePose());
  ASSERT_FALSE(bad_params.ok());
  EXPECT_NE(bad_params.error().find("robust_scale"), std::string::npos);
}

TEST_F(AnalyticTracking, UnobservedFieldIsLostNotTracked) {
  // A map that has seen nothing near this view: no point can be matched.
  synthetic::LabeledScene far_scene;
  synthetic::Sphere ball;
  ball.center = Eigen::Vector3d(50.0, 50.0, 50.0);
  far_scene.add({"ball", ball, 1});
  const AnalyticField field(far_scene, 0.04f);
  SdfTracker tracker;
  Result<Alignment> aligned = tracker.align(view_->depth, view_->intrinsics, field, referencePose());
  ASSERT_TRUE(aligned.ok());
  EXPECT_EQ(aligned.value().lost_reason, LostReason::kTooFewInliers);
  EXPECT_TRUE(aligned.value().pose.isApprox(referencePose()));
}

}  // namespace
}  // namespace semfuse::tracking::testing
