#include "semfuse/datasets/tum_trajectory.hpp"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace semfuse::datasets {
namespace {

namespace fs = std::filesystem;

class TumTrajectory : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    file_ = fs::temp_directory_path() /
            ("semfuse_trajectory_" + std::string(test->name()) + "_" + std::to_string(::getpid()) + ".txt");
  }
  void TearDown() override { fs::remove(file_); }
  void write(const std::string& text) { std::ofstream(file_) << text; }
  fs::path file_;
};

TEST_F(TumTrajectory, ReadsWhatSemfuseQueryPosesWritesSortedByTime) {
  // Nanosecond stamps and a header comment, out of order as two cameras' poses can be.
  write(
      "# timestamp tx ty tz qx qy qz qw (camera-to-world, seconds of the frame's stamp)\n"
      "1305031102.275326000 1.0 2.0 3.0 0 0 0.707106781 0.707106781\n"
      "1305031102.175304000 0.5 0.0 0.0 0 0 0 1\n");
  auto trajectory = readTumTrajectory(file_);
  ASSERT_TRUE(trajectory.ok()) << trajectory.error();
  ASSERT_EQ(trajectory.value().size(), 2u);
  EXPECT_NEAR(trajectory.value()[0].time, 1305031102.175304, 1e-6);
  EXPECT_NEAR(trajectory.value()[1].pose.translation().z(), 3.0, 1e-12);
  // 90 degrees about z: the camera's x axis points along world y.
  EXPECT_NEAR(trajectory.value()[1].pose.linear()(1, 0), 1.0, 1e-9);
}

TEST_F(TumTrajectory, PoseAtInterpolatesWithinTheWindowAndFallsBackToTheNearestSample) {
  write("10.00 0 0 0 0 0 0 1\n10.01 0.01 0 0 0 0 0 1\n10.50 1 0 0 0 0 0 1\n");
  auto trajectory = readTumTrajectory(file_);
  ASSERT_TRUE(trajectory.ok()) << trajectory.error();
  const auto& poses = trajectory.value();
  auto between = trajectoryPoseAt(poses, 10.005, 0.02);
  ASSERT_TRUE(between);
  EXPECT_NEAR(between->translation().x(), 0.005, 1e-9);
  // 10.49: the sample before is 0.48 s away, only the one after is within 20 ms.
  auto near_end = trajectoryPoseAt(poses, 10.49, 0.02);
  ASSERT_TRUE(near_end);
  EXPECT_NEAR(near_end->translation().x(), 1.0, 1e-12);
  EXPECT_FALSE(trajectoryPoseAt(poses, 10.2, 0.02));
  EXPECT_FALSE(trajectoryPoseAt(poses, 9.0, 0.02));
}

TEST_F(TumTrajectory, MalformedLinesNameTheFileAndLine) {
  write("# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0.5 0.5\n");
  auto not_unit = readTumTrajectory(file_);
  ASSERT_FALSE(not_unit.ok());
  EXPECT_NE(not_unit.error().find(":3: quaternion norm"), std::string::npos) << not_unit.error();
  write("1.0 0 0 0 0 0 0\n");
  auto short_line = readTumTrajectory(file_);
  ASSERT_FALSE(short_line.ok());
  EXPECT_NE(short_line.error().find(":1: expected 'timestamp tx ty tz qx qy qz qw'"), std::string::npos)
      << short_line.error();
  write("nan 0 0 0 0 0 0 1\n");
  EXPECT_FALSE(readTumTrajectory(file_).ok());
  EXPECT_FALSE(readTumTrajectory(file_.string() + ".missing").ok());
}

}  // namespace
}  // namespace semfuse::datasets
