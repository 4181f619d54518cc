// The one camera check: each bad intrinsic or pose gets its own message, with the numbers
// measured, and the invalid-argument code; a good camera passes, as do 7-Scenes-like poses that
// are orthonormal only to a few 1e-4.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "semfuse/core/camera_check.hpp"

using namespace semfuse;

namespace {

const PinholeIntrinsics kKinect{640, 480, 585.0, 585.0, 320.0, 240.0};
const double kNaN = std::numeric_limits<double>::quiet_NaN();
const double kInf = std::numeric_limits<double>::infinity();

std::string intrinsicsError(PinholeIntrinsics k, int max_side = kAnyImageSide) {
  Status status = checkIntrinsics(k, max_side);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.errorCode(), ErrorCode::kInvalidArgument) << status.error();
  return status.error();
}

std::string poseError(const Pose& pose) {
  Status status = checkRigidPose(pose);
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.errorCode(), ErrorCode::kInvalidArgument) << status.error();
  return status.error();
}

PinholeIntrinsics with(PinholeIntrinsics k, double PinholeIntrinsics::*field, double value) {
  k.*field = value;
  return k;
}

}  // namespace

TEST(CameraCheck, AGoodCameraPasses) {
  EXPECT_TRUE(checkIntrinsics(kKinect).ok());
  EXPECT_TRUE(checkIntrinsics(kKinect, 640).ok());
  EXPECT_TRUE(checkRigidPose(Pose::Identity()).ok());
  Pose turned = Pose::Identity();
  turned.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  turned.translation() = Eigen::Vector3d(1.0, -2.0, 0.5);
  EXPECT_TRUE(checkCamera(kKinect, turned).ok());
}

TEST(CameraCheck, EachBadImageSizeGetsItsMessage) {
  PinholeIntrinsics empty = kKinect;
  empty.width = 0;
  EXPECT_EQ(intrinsicsError(empty), "intrinsics: image size 0x480 is empty");
  empty = kKinect;
  empty.height = -5;
  EXPECT_EQ(intrinsicsError(empty), "intrinsics: image size 640x-5 is empty");
  EXPECT_EQ(intrinsicsError(kKinect, 512), "intrinsics: image size 640x480 exceeds the 512-pixel limit");
}

TEST(CameraCheck, EachBadFocalLengthOrPrincipalPointGetsItsMessage) {
  using K = PinholeIntrinsics;
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::fx, 0.0)),
            "intrinsics: focal lengths must be finite and > 0, got fx=0 fy=585");
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::fy, -3.0)),
            "intrinsics: focal lengths must be finite and > 0, got fx=585 fy=-3");
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::fx, kNaN)),
            "intrinsics: focal lengths must be finite and > 0, got fx=nan fy=585");
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::fy, kInf)),
            "intrinsics: focal lengths must be finite and > 0, got fx=585 fy=inf");
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::cx, kNaN)),
            "intrinsics: principal point must be finite, got cx=nan cy=240");
  EXPECT_EQ(intrinsicsError(with(kKinect, &K::cy, -kInf)),
            "intrinsics: principal point must be finite, got cx=320 cy=-inf");
  // A principal point outside the image is unusual but a valid pinhole camera (a crop).
  EXPECT_TRUE(checkIntrinsics(with(kKinect, &K::cx, -100.0)).ok());
}

TEST(CameraCheck, ProjectionAloneIgnoresTheImageSize) {
  PinholeIntrinsics no_size = kKinect;
  no_size.width = no_size.height = 0;
  EXPECT_TRUE(checkProjection(no_size).ok());
  no_size.fx = 0.0;
  EXPECT_EQ(checkProjection(no_size).error(), "intrinsics: focal lengths must be finite and > 0, got fx=0 fy=585");
}

TEST(CameraCheck, EachBadPoseGetsItsMessage) {
  Pose pose = Pose::Identity();
  pose.matrix()(1, 2) = kNaN;
  EXPECT_EQ(poseError(pose), "pose: non-finite value nan at row 1, column 2");

  pose = Pose::Identity();
  pose.translation().x() = kInf;
  EXPECT_EQ(poseError(pose), "pose: non-finite value inf at row 0, column 3");

  pose = Pose::Identity();
  pose.matrix()(3, 0) = 0.5;
  EXPECT_EQ(poseError(pose), "pose: bottom row must be [0 0 0 1], got [0.5 0 0 1]");

  pose = Pose::Identity();
  pose.linear()(0, 0) = 1.5;  // first column scaled: |R^T R - I| = 1.25
  EXPECT_EQ(poseError(pose), "pose: rotation is not orthonormal (|R^T R - I| = 1.25, tolerance 0.001)");

  pose = Pose::Identity();
  pose.linear()(2, 2) = -1.0;
  EXPECT_EQ(poseError(pose), "pose: rotation is a reflection (determinant -1)");
}

TEST(CameraCheck, OneToleranceForEveryPose) {
  // Rotations written with 4-5 digits, as dataset pose files are, drift by ~4e-4: accepted.
  Pose rounded = Pose::Identity();
  rounded.linear() << 0.9998, 0.0, 0.0, 0.0, 1.0002, 0.0, 0.0, 0.0, 1.0;
  EXPECT_TRUE(checkRigidPose(rounded).ok());
  // Past kRotationTolerance it is refused, with the measured error in the message.
  Pose drifted = Pose::Identity();
  drifted.linear()(0, 0) = 1.001;
  EXPECT_EQ(poseError(drifted), "pose: rotation is not orthonormal (|R^T R - I| = 0.002001, tolerance 0.001)");
}

TEST(CameraCheck, CameraChecksIntrinsicsFirstThenThePose) {
  Pose mirror = Pose::Identity();
  mirror.linear()(2, 2) = -1.0;
  PinholeIntrinsics no_focal = kKinect;
  no_focal.fx = 0.0;
  EXPECT_EQ(checkCamera(no_focal, mirror).error(), "intrinsics: focal lengths must be finite and > 0, got fx=0 fy=585");
  EXPECT_EQ(checkCamera(kKinect, mirror).error(), "pose: rotation is a reflection (determinant -1)");
  EXPECT_EQ(checkCamera(kKinect, mirror).errorCode(), ErrorCode::kInvalidArgument);
}
