// The ROS 2 input's logic without DDS: tf chains and interpolation, pairing depth with colour by
// stamp, waiting bounded by time and count, and each image given up reported with its reason.
#include <gtest/gtest.h>

#include <cmath>

#include "ros_frame_assembler.hpp"
#include "ros_tf_buffer.hpp"

using namespace semfuse;
using namespace semfuse::server;
using Clock = RosFrameAssembler::Clock;
using namespace std::chrono_literals;

namespace {

Pose translation(double x, double y, double z) {
  Pose p = Pose::Identity();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

Pose rotationZ(double degrees) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(degrees * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

Stamp at(double seconds) {
  const auto sec = static_cast<int32_t>(std::floor(seconds));
  return {sec, static_cast<uint32_t>(std::lround((seconds - sec) * 1e9))};
}

cv::Mat depthImage(int w = 4, int h = 3) { return cv::Mat(h, w, CV_32FC1, cv::Scalar(1.5f)); }
cv::Mat colorImage(uint8_t r, int w = 4, int h = 3) { return cv::Mat(h, w, CV_8UC3, cv::Scalar(r, 0, 0)); }

PinholeIntrinsics intrinsics(int w = 4, int h = 3) { return {w, h, 2.0, 2.0, 1.5, 1.0}; }

}  // namespace

TEST(TfBuffer, ComposesAChainAndInterpolatesBetweenStamps) {
  TfBuffer tf;
  // map -> odom (static), odom -> base moving 1 m along x per second, base -> camera rotated.
  ASSERT_TRUE(tf.add("map", "odom", translation(0, 2, 0), at(0), true).ok());
  ASSERT_TRUE(tf.add("odom", "base", translation(0, 0, 0), at(10.0), false).ok());
  ASSERT_TRUE(tf.add("odom", "base", translation(1, 0, 0) * rotationZ(90), at(11.0), false).ok());
  ASSERT_TRUE(tf.add("base", "camera", translation(0, 0, 0.5), at(0), true).ok());

  auto mid = tf.lookup("map", "camera", at(10.5));
  ASSERT_TRUE(mid.ok()) << mid.error();
  EXPECT_NEAR(mid.value().translation().x(), 0.5, 1e-9);
  EXPECT_NEAR(mid.value().translation().y(), 2.0, 1e-9);
  EXPECT_NEAR(mid.value().translation().z(), 0.5, 1e-9);
  const double yaw = std::atan2(mid.value().linear()(1, 0), mid.value().linear()(0, 0)) * 180.0 / M_PI;
  EXPECT_NEAR(yaw, 45.0, 1e-6);  // slerp half way

  // The inverse direction, between two branches of the tree.
  ASSERT_TRUE(tf.add("map", "tag", translation(3, 2, 0), at(0), true).ok());
  auto tag_in_camera = tf.lookup("camera", "tag", at(10.0));
  ASSERT_TRUE(tag_in_camera.ok()) << tag_in_camera.error();
  EXPECT_NEAR(tag_in_camera.value().translation().x(), 3.0, 1e-9);
  EXPECT_NEAR(tag_in_camera.value().translation().z(), -0.5, 1e-9);
}

TEST(TfBuffer, RefusesWhatItCannotAnswer) {
  TfBuffer tf;
  ASSERT_TRUE(tf.add("map", "camera", translation(1, 0, 0), at(5.0), false).ok());
  ASSERT_TRUE(tf.add("map", "camera", translation(2, 0, 0), at(6.0), false).ok());
  auto later = tf.lookup("map", "camera", at(6.5));  // no extrapolation
  ASSERT_FALSE(later.ok());
  EXPECT_NE(later.error().find("outside its history"), std::string::npos) << later.error();
  auto other_tree = tf.lookup("map", "lidar", at(5.5));
  ASSERT_FALSE(other_tree.ok());
  EXPECT_NE(other_tree.error().find("no tf path"), std::string::npos) << other_tree.error();
  EXPECT_FALSE(tf.add("", "camera", Pose::Identity(), at(1), false).ok());
  EXPECT_FALSE(tf.add("camera", "camera", Pose::Identity(), at(1), false).ok());
  // A loop made by a bad publisher is an error, not a hang.
  ASSERT_TRUE(tf.add("b", "a", Pose::Identity(), at(1), true).ok());
  ASSERT_TRUE(tf.add("a", "b", Pose::Identity(), at(1), true).ok());
  auto loop = tf.lookup("map", "a", at(1));
  ASSERT_FALSE(loop.ok());
  EXPECT_NE(loop.error().find("loop"), std::string::npos) << loop.error();
}

TEST(TfBuffer, ForgetsSamplesOlderThanItsHistory) {
  TfBuffer tf(2.0);
  for (int i = 0; i <= 10; ++i) ASSERT_TRUE(tf.add("map", "cam", translation(i, 0, 0), at(i), false).ok());
  EXPECT_FALSE(tf.lookup("map", "cam", at(5.0)).ok());
  auto recent = tf.lookup("map", "cam", at(9.25));
  ASSERT_TRUE(recent.ok());
  EXPECT_NEAR(recent.value().translation().x(), 9.25, 1e-9);
}

class AssemblerTest : public ::testing::Test {
 protected:
  RosFrameAssembler::Options options() {
    RosFrameAssembler::Options o;
    o.camera_id = "cam";
    o.pair_tolerance_s = 0.01;
    o.wait_s = 0.5;
    o.pending_depth = 3;
    o.pending_color = 4;
    o.use_tf = true;
    return o;
  }
  TfBuffer tf;
  RosFrameAssembler::PoseLookup lookup = [this](const std::string& frame, Stamp s) {
    return tf.lookup("map", frame, s);
  };
  Clock::time_point t0 = Clock::now();
  std::vector<Frame> frames;
  std::vector<RosFrameAssembler::Drop> drops;
};

TEST_F(AssemblerTest, PairsByClosestStampAndTakesThePoseFromTf) {
  RosFrameAssembler a(options());
  a.setIntrinsics(intrinsics());
  ASSERT_TRUE(tf.add("map", "optical", translation(1, 2, 3), at(100.0), true).ok());
  EXPECT_FALSE(a.addColor(at(99.990), colorImage(10)));
  EXPECT_FALSE(a.addColor(at(100.004), colorImage(20)));  // the closest to 100.000
  EXPECT_FALSE(a.addColor(at(100.033), colorImage(30)));
  EXPECT_FALSE(a.addDepth(1, at(100.0), "optical", depthImage(), t0));
  a.poll(t0, lookup, frames, drops);
  ASSERT_EQ(frames.size(), 1u);
  const Frame& f = frames[0];
  EXPECT_EQ(f.camera_id, "cam");
  EXPECT_EQ(f.seq, 1u);
  EXPECT_EQ(f.frame_id, "optical");
  EXPECT_EQ(f.intrinsics.fx, 2.0);
  EXPECT_EQ(f.color.at<cv::Vec3b>(0, 0)[0], 20);
  ASSERT_TRUE(f.camera_to_world.has_value());
  EXPECT_NEAR(f.camera_to_world->translation().z(), 3.0, 1e-12);
  // The older colour could pair with nothing any more; the newer one waits for its depth.
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_STREQ(drops[0].reason, ros_reason::kColorUnpaired);
  EXPECT_EQ(a.pendingColor(), 1u);
}

TEST_F(AssemblerTest, WaitsBoundedThenDropsWithTheReason) {
  RosFrameAssembler a(options());
  a.addDepth(1, at(1.0), "optical", depthImage(), t0);
  a.poll(t0 + 100ms, lookup, frames, drops);
  EXPECT_TRUE(frames.empty());
  EXPECT_TRUE(drops.empty());  // still within --ros.wait
  a.poll(t0 + 600ms, lookup, frames, drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_STREQ(drops[0].reason, ros_reason::kNoCameraInfo);
  EXPECT_EQ(drops[0].seq, 1u);

  drops.clear();
  a.setIntrinsics(intrinsics());
  a.addDepth(2, at(2.0), "optical", depthImage(), t0);
  a.addColor(at(2.5), colorImage(1));  // far outside the 10 ms tolerance
  a.poll(t0 + 600ms, lookup, frames, drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_STREQ(drops[0].reason, ros_reason::kNoColor);

  drops.clear();
  a.addDepth(3, at(2.5), "optical", depthImage(), t0);  // colour pairs, but no tf ever came
  a.poll(t0 + 600ms, lookup, frames, drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_STREQ(drops[0].reason, ros_reason::kNoTf);
  EXPECT_TRUE(frames.empty());
}

TEST_F(AssemblerTest, BoundsTheWaitingListsAndKeepsOrder) {
  RosFrameAssembler a(options());
  a.setIntrinsics(intrinsics());
  for (uint64_t s = 1; s <= 3; ++s) EXPECT_FALSE(a.addDepth(s, at(s), "optical", depthImage(), t0));
  auto dropped = a.addDepth(4, at(4), "optical", depthImage(), t0);
  ASSERT_TRUE(dropped);
  EXPECT_STREQ(dropped->reason, ros_reason::kDepthQueueFull);
  EXPECT_EQ(dropped->seq, 1u);
  // Colour for 2, 3 and 4 arrives (out of order); tf arrives: all three leave, in seq order.
  a.addColor(at(3), colorImage(3));
  a.addColor(at(2), colorImage(2));
  a.addColor(at(4), colorImage(4));
  ASSERT_TRUE(tf.add("map", "optical", translation(0, 0, 0), at(0), true).ok());
  a.poll(t0 + 10ms, lookup, frames, drops);
  ASSERT_EQ(frames.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(frames[i].seq, i + 2);
    EXPECT_EQ(static_cast<size_t>(frames[i].color.at<cv::Vec3b>(0, 0)[0]), i + 2);
  }

  // At most pending_color (4) colour images are kept: the oldest goes first.
  RosFrameAssembler b(options());
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(b.addColor(at(10 + i), colorImage(1)));
  auto full = b.addColor(at(20), colorImage(1));
  ASSERT_TRUE(full);
  EXPECT_STREQ(full->reason, ros_reason::kColorUnpaired);
  EXPECT_EQ(b.pendingColor(), 4u);
}

TEST_F(AssemblerTest, RejectsMismatchedSizesAndTracksThroughTfGaps) {
  auto o = options();
  o.camera_frame = "configured_optical";  // overrides the image's frame id
  RosFrameAssembler a(o);
  a.setIntrinsics(intrinsics(8, 6));
  a.addDepth(1, at(1), "ignored", depthImage(), t0);
  a.poll(t0, lookup, frames, drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_TRUE(drops[0].rejected);
  EXPECT_NE(drops[0].message.find("CameraInfo 8x6"), std::string::npos) << drops[0].message;

  drops.clear();
  a.setIntrinsics(intrinsics());
  a.addDepth(2, at(2), "ignored", depthImage(), t0);
  a.addColor(at(2), colorImage(1, 8, 6));
  a.poll(t0, lookup, frames, drops);
  ASSERT_EQ(drops.size(), 1u);
  EXPECT_TRUE(drops[0].rejected);
  EXPECT_NE(drops[0].message.find("not registered"), std::string::npos) << drops[0].message;

  // tf for 3, then a gap at 4: frame 4 goes without a pose (tracked) after the wait.
  drops.clear();
  ASSERT_TRUE(tf.add("map", "configured_optical", translation(0, 0, 1), at(3), false).ok());
  a.addDepth(3, at(3), "ignored", depthImage(), t0);
  a.addColor(at(3), colorImage(3));
  a.addDepth(4, at(4), "ignored", depthImage(), t0);
  a.addColor(at(4), colorImage(4));
  a.poll(t0 + 100ms, lookup, frames, drops);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].frame_id, "configured_optical");
  EXPECT_TRUE(frames[0].camera_to_world.has_value());
  a.poll(t0 + 600ms, lookup, frames, drops);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].seq, 4u);
  EXPECT_FALSE(frames[1].camera_to_world.has_value());
  EXPECT_TRUE(drops.empty());
}

TEST_F(AssemblerTest, WithoutTfOrColourEveryDepthLeavesAtOnceUnposed) {
  auto o = options();
  o.use_tf = false;
  o.expect_color = false;
  RosFrameAssembler a(o);
  a.setIntrinsics(intrinsics());
  a.addDepth(1, at(1), "", depthImage(), t0);
  a.poll(t0, lookup, frames, drops);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_FALSE(frames[0].camera_to_world.has_value());
  EXPECT_TRUE(frames[0].color.empty());
}
