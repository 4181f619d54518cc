#include "semfuse/datasets/tum_rgbd.hpp"

#include <fstream>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

namespace semfuse::datasets {
namespace {

namespace fs = std::filesystem;

// A TUM-style folder built in the test: 3 depth images, colour images offset by a few ms (one
// of them too far away to pair), ground truth at 100 Hz.
class TumFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    // ctest runs each test as its own process, in parallel: one folder per test and process, or
    // one test's TearDown deletes the folder another is reading.
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("semfuse_tum_test_" + std::string(test->name()) + "_" + std::to_string(::getpid())) /
           "rgbd_dataset_freiburg2_unit";
    fs::remove_all(dir_.parent_path());
    fs::create_directories(dir_ / "rgb");
    fs::create_directories(dir_ / "depth");
  }
  void TearDown() override { fs::remove_all(dir_.parent_path()); }

  void writeText(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }

  void writeImages(cv::Size size) {
    for (int i = 0; i < 3; ++i) {
      // Depth i: 5000 * (1 + i) units = (1 + i) metres; pixel (0,0) invalid.
      cv::Mat depth(size, CV_16UC1, cv::Scalar(5000 * (1 + i)));
      depth.at<uint16_t>(0, 0) = 0;
      ASSERT_TRUE(cv::imwrite((dir_ / ("depth/" + std::to_string(i) + ".png")).string(), depth));
      // Colour: pure red in RGB (written as BGR by OpenCV).
      cv::Mat bgr(size, CV_8UC3, cv::Scalar(0, 0, 200));
      ASSERT_TRUE(cv::imwrite((dir_ / ("rgb/" + std::to_string(i) + ".png")).string(), bgr));
    }
    writeText("depth.txt",
              "# depth maps\n# file: 'unit'\n# timestamp filename\n"
              "100.000 depth/0.png\n100.033 depth/1.png\n100.066 depth/2.png\n");
    // rgb 2 is 30 ms from depth 2: outside the 20 ms window, so depth 2 is skipped.
    writeText("rgb.txt", "# color images\n100.010 rgb/0.png\n100.030 rgb/1.png\n100.096 rgb/2.png\n");
  }
  fs::path dir_;
};

TEST_F(TumFolder, AssociatesByNearestTimeAndScalesDepthBy5000) {
  writeImages(cv::Size(640, 480));
  // Ground truth: identity at t=100.0, a 90 degree turn about z plus a translation at t=100.035.
  writeText("groundtruth.txt",
            "# timestamp tx ty tz qx qy qz qw\n"
            "100.000 0 0 0 0 0 0 1\n"
            "100.035 1.5 -2 0.25 0 0 0.7071067811865476 0.7071067811865476\n");
  auto reader = TumRgbdReader::open(dir_);
  ASSERT_TRUE(reader.ok()) << reader.error();
  // freiburg2 from the folder name.
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().fx, 520.9);
  EXPECT_DOUBLE_EQ(reader.value().intrinsics().cy, 249.7);
  ASSERT_EQ(reader.value().count(), 2u);
  EXPECT_EQ(reader.value().entry(0).color_file, fs::path("rgb/0.png"));
  EXPECT_EQ(reader.value().entry(1).color_file, fs::path("rgb/1.png"));

  auto first = reader.value().load(0);
  ASSERT_TRUE(first.ok()) << first.error();
  EXPECT_FLOAT_EQ(first.value().depth.at<float>(10, 10), 1.0f);
  EXPECT_FLOAT_EQ(first.value().depth.at<float>(0, 0), 0.0f);
  EXPECT_EQ(first.value().color.at<cv::Vec3b>(5, 5), cv::Vec3b(200, 0, 0));  // RGB order
  EXPECT_EQ(first.value().stamp.sec, 100);
  EXPECT_EQ(first.value().stamp.nanosec, 0u);
  ASSERT_TRUE(first.value().camera_to_world.has_value());
  EXPECT_TRUE(first.value().camera_to_world->isApprox(Pose::Identity()));

  auto second = reader.value().load(1);
  ASSERT_TRUE(second.ok()) << second.error();
  EXPECT_FLOAT_EQ(second.value().depth.at<float>(10, 10), 2.0f);
  EXPECT_EQ(second.value().stamp.nanosec, 33000000u);
  ASSERT_TRUE(second.value().camera_to_world.has_value());
  const Pose& pose = *second.value().camera_to_world;
  // Only the sample at 100.035 is within 20 ms of depth 1 (100.033): that sample, as it is.
  EXPECT_TRUE(pose.translation().isApprox(Eigen::Vector3d(1.5, -2, 0.25)));
  // Rotation of +90 degrees about z maps x to y.
  EXPECT_TRUE((pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), 1e-9));
}

TEST_F(TumFolder, GroundTruthIsInterpolatedBetweenTheSamplesAroundTheDepthStamp) {
  writeImages(cv::Size(64, 48));
  // Depth 1 at 100.033 lies 8 ms after the first sample and 12 ms before the second: 0.4 of the way.
  writeText("groundtruth.txt",
            "100.025 0 0 0 0 0 0 1\n"
            "100.045 1.5 -2 0.25 0 0 0.7071067811865476 0.7071067811865476\n");
  auto reader = TumRgbdReader::open(dir_, {"tum", PinholeIntrinsics{64, 48, 50, 50, 32, 24}});
  ASSERT_TRUE(reader.ok()) << reader.error();
  ASSERT_TRUE(reader.value().entry(1).camera_to_world.has_value());
  const Pose& pose = *reader.value().entry(1).camera_to_world;
  EXPECT_TRUE(pose.translation().isApprox(0.4 * Eigen::Vector3d(1.5, -2, 0.25), 1e-9));
  const Eigen::AngleAxisd turn(pose.linear());
  EXPECT_NEAR(turn.angle(), 0.4 * M_PI / 2, 1e-9);
  EXPECT_TRUE(turn.axis().isApprox(Eigen::Vector3d::UnitZ(), 1e-9));
}

TEST_F(TumFolder, WithoutGroundTruthFramesHaveNoPose) {
  writeImages(cv::Size(640, 480));
  auto reader = TumRgbdReader::open(dir_);
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto frame = reader.value().loadDepthOnly(0);
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_FALSE(frame.value().camera_to_world.has_value());
  EXPECT_TRUE(frame.value().color.empty());
}

TEST_F(TumFolder, GivenIntrinsicsOverrideTheFolderName) {
  writeImages(cv::Size(8, 6));
  TumRgbdOptions options;
  options.intrinsics = PinholeIntrinsics{8, 6, 10.0, 10.0, 3.5, 2.5};
  auto reader = TumRgbdReader::open(dir_, options);
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto frame = reader.value().load(1);
  ASSERT_TRUE(frame.ok()) << frame.error();
  EXPECT_EQ(frame.value().depth.size(), cv::Size(8, 6));
  EXPECT_DOUBLE_EQ(frame.value().intrinsics.fx, 10.0);
}

TEST_F(TumFolder, ImageSizeDisagreeingWithIntrinsicsIsRejected) {
  writeImages(cv::Size(8, 6));
  auto reader = TumRgbdReader::open(dir_);  // freiburg2: 640x480
  ASSERT_TRUE(reader.ok()) << reader.error();
  auto frame = reader.value().load(0);
  ASSERT_FALSE(frame.ok());
  EXPECT_NE(frame.error().find("is 8x6, the intrinsics are for 640x480"), std::string::npos) << frame.error();
}

TEST_F(TumFolder, MalformedListsAndMissingFilesAreRejectedPrecisely) {
  writeImages(cv::Size(8, 6));
  writeText("groundtruth.txt", "100.0 0 0 0 0 0 0\n");
  auto short_line = TumRgbdReader::open(dir_);
  ASSERT_FALSE(short_line.ok());
  EXPECT_NE(short_line.error().find("groundtruth.txt:1: expected 'timestamp tx ty tz qx qy qz qw'"), std::string::npos)
      << short_line.error();

  writeText("groundtruth.txt", "100.0 0 0 0 0 0 0 2\n");
  auto bad_quaternion = TumRgbdReader::open(dir_);
  ASSERT_FALSE(bad_quaternion.ok());
  EXPECT_NE(bad_quaternion.error().find("quaternion norm 2.0"), std::string::npos) << bad_quaternion.error();

  fs::remove(dir_ / "groundtruth.txt");
  fs::remove(dir_ / "rgb.txt");
  auto no_rgb = TumRgbdReader::open(dir_);
  ASSERT_FALSE(no_rgb.ok());
  EXPECT_NE(no_rgb.error().find("rgb.txt"), std::string::npos) << no_rgb.error();
}

TEST(TumRgbd, FreiburgCameraFromFolderName) {
  EXPECT_EQ(tumFreiburgNumberFromName("rgbd_dataset_freiburg1_xyz"), 1);
  EXPECT_EQ(tumFreiburgNumberFromName("rgbd_dataset_freiburg3_long_office_household"), 3);
  EXPECT_FALSE(tumFreiburgNumberFromName("my_kitchen").has_value());
  EXPECT_DOUBLE_EQ(tumFreiburgIntrinsics(3)->fy, 539.2);
  auto reader = TumRgbdReader::open(fs::temp_directory_path());
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().find("give the intrinsics"), std::string::npos) << reader.error();
}

}  // namespace
}  // namespace semfuse::datasets
