#include "semfuse/datasets/seven_scenes.hpp"

#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "shared_data.hpp"

namespace semfuse::datasets {
namespace {

namespace fs = std::filesystem;

TEST(SevenScenes, RedkitchenFrameZeroHasKinectIntrinsicsMetricDepthAndRigidPose) {
  const fs::path folder = semfuse::testing::redkitchenDir();
  SEMFUSE_REQUIRE_SHARED_DIR(folder);
  auto reader = SevenScenesReader::open(folder);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ(reader.value().count(), 500u);
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().fx, 585.0);
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().fy, 585.0);
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().cx, 320.0);
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().cy, 240.0);
  EXPECT_EQ(reader.value().intrinsics().width, 640);
  EXPECT_EQ(reader.value().intrinsics().height, 480);

  auto frame = reader.value().load(0);
  ASSERT_TRUE(frame.ok()) << frame.error();
  const Frame& f = frame.value();
  EXPECT_EQ(f.seq, 0u);
  ASSERT_EQ(f.depth.type(), CV_32FC1);
  ASSERT_EQ(f.color.type(), CV_8UC3);
  EXPECT_EQ(f.depth.size(), cv::Size(640, 480));
  EXPECT_EQ(f.color.size(), cv::Size(640, 480));

  // A kitchen seen by a Kinect: valid depth between 0.3 m and 8 m, most pixels valid, and no
  // raw 65535 (65.535 m) left through.
  const cv::Mat valid = f.depth > 0.0f;
  const int valid_count = cv::countNonZero(valid);
  EXPECT_GT(valid_count, 640 * 480 / 2);
  double min_depth = 0.0, max_depth = 0.0;
  cv::minMaxLoc(f.depth, nullptr, &max_depth);
  cv::minMaxLoc(f.depth, &min_depth, nullptr, nullptr, nullptr, valid);
  EXPECT_GT(min_depth, 0.3);
  EXPECT_LT(max_depth, 8.0);

  ASSERT_TRUE(f.camera_to_world.has_value());
  const Eigen::Matrix3d rotation = f.camera_to_world->linear();
  // The reference poses are stored with ~2e-4 orthonormality error (measured): a real rotation,
  // but any pose validation must allow for it.
  EXPECT_LT((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm(), 1e-3);
  EXPECT_NEAR(rotation.determinant(), 1.0, 1e-3);
  // First entry of frame-000000.pose.txt and its translation.
  EXPECT_NEAR(f.camera_to_world->matrix()(0, 0), 0.9093129, 1e-7);
  EXPECT_NEAR(f.camera_to_world->translation().x(), -0.34045634, 1e-7);
}

TEST(SevenScenes, DepthOnlyLoadSkipsColourButKeepsDepthAndPose) {
  const fs::path folder = semfuse::testing::redkitchenDir();
  SEMFUSE_REQUIRE_SHARED_DIR(folder);
  auto reader = SevenScenesReader::open(folder);
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto full = reader.value().load(42);
  auto fast = reader.value().loadDepthOnly(42);
  ASSERT_TRUE(full.ok() && fast.ok());
  EXPECT_TRUE(fast.value().color.empty());
  EXPECT_EQ(cv::norm(full.value().depth, fast.value().depth, cv::NORM_INF), 0.0);
  EXPECT_TRUE(fast.value().camera_to_world->isApprox(*full.value().camera_to_world));
  EXPECT_EQ(fast.value().seq, 42u);
}

class SevenScenesFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("semfuse_7scenes_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  fs::path dir_;
};

TEST_F(SevenScenesFolder, MillimetresBecomeMetresAndSaturatedPixelsInvalid) {
  write("camera-intrinsics.txt", "100 0 2\n0 110 1.5\n0 0 1\n");
  cv::Mat depth(3, 4, CV_16UC1, cv::Scalar(1500));
  depth.at<uint16_t>(0, 0) = 0;
  depth.at<uint16_t>(1, 1) = 65535;
  ASSERT_TRUE(cv::imwrite((dir_ / "frame-000007.depth.png").string(), depth));
  auto reader = SevenScenesReader::open(dir_);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_EQ(reader.value().frameNumber(0), 7u);
  auto frame = reader.value().loadDepthOnly(0);
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_FLOAT_EQ(frame.value().depth.at<float>(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(frame.value().depth.at<float>(1, 1), 0.0f);
  EXPECT_FLOAT_EQ(frame.value().depth.at<float>(2, 3), 1.5f);
  EXPECT_FALSE(frame.value().camera_to_world.has_value());  // no pose file
  EXPECT_DOUBLE_EQ(frame.value().intrinsics.fy, 110.0);
  EXPECT_EQ(frame.value().intrinsics.width, 4);
  // load() needs the colour image, which is missing.
  auto full = reader.value().load(0);
  ASSERT_FALSE(full.ok());
  EXPECT_NE(full.error().find("colour image missing"), std::string::npos) << full.error();
  EXPECT_NE(full.error().find("frame-000007.color.jpg"), std::string::npos) << full.error();
}

TEST_F(SevenScenesFolder, EmptyFolderIsRejected) {
  auto reader = SevenScenesReader::open(dir_);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("no frame-NNNNNN.depth.png"), std::string::npos) << reader.error();
}

TEST_F(SevenScenesFolder, MalformedIntrinsicsAreRejected) {
  write("camera-intrinsics.txt", "585 0 320\n0 585 240\n");
  ASSERT_TRUE(cv::imwrite((dir_ / "frame-000000.depth.png").string(), cv::Mat(2, 2, CV_16UC1, cv::Scalar(1))));
  auto reader = SevenScenesReader::open(dir_);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("6 numbers, expected 9"), std::string::npos) << reader.error();
}

TEST_F(SevenScenesFolder, CorruptDepthAndPoseFilesGiveTheirOwnErrors) {
  write("camera-intrinsics.txt", "585 0 320\n0 585 240\n0 0 1\n");
  ASSERT_TRUE(cv::imwrite((dir_ / "frame-000000.depth.png").string(), cv::Mat(2, 2, CV_16UC1, cv::Scalar(1))));
  write("frame-000001.depth.png", "not a png");
  write("frame-000000.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 abc 1\n");
  auto reader = SevenScenesReader::open(dir_);
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto bad_pose = reader.value().loadDepthOnly(0);
  ASSERT_FALSE(bad_pose.ok());
  EXPECT_NE(bad_pose.error().find("'abc' is not a number"), std::string::npos) << bad_pose.error();
  auto bad_depth = reader.value().loadDepthOnly(1);
  ASSERT_FALSE(bad_depth.ok());
  EXPECT_NE(bad_depth.error().find("cannot be decoded"), std::string::npos) << bad_depth.error();
  auto out_of_range = reader.value().loadDepthOnly(2);
  ASSERT_FALSE(out_of_range.ok());
  EXPECT_NE(out_of_range.error().find("out of range (2 frames)"), std::string::npos) << out_of_range.error();
}

}  // namespace
}  // namespace semfuse::datasets
