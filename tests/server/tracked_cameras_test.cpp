// Cameras without poses through a real semfuse-server over loopback DDS: the first builds the map
// from nothing, a second joins it later without a pose and is placed by relocalisation, and
// `semfuse-query poses` records the trajectory the server estimated, which is compared with the
// synthetic room's exact poses.
#include <sys/wait.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "eventually.hpp"
#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr double kTrackedMapVoxel = 0.02;

synthetic::SequenceConfig sequenceConfig(const std::string& camera_id) {
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);  // 320x240 keeps the test quick
  config.trajectory.frame_count = 300;                // 1.2 degrees and 3.4 cm of orbit per frame
  config.camera_id = camera_id;
  return config;
}

// One row of `semfuse-query poses --format csv`.
struct RecordedPose {
  std::string camera_id;
  uint64_t seq = 0;
  bool posed = false;
  Pose camera_to_world = Pose::Identity();
};

std::vector<RecordedPose> readCsvTrajectory(const std::filesystem::path& file) {
  std::vector<RecordedPose> out;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream stream(line);
    for (std::string field; std::getline(stream, field, ',');) fields.push_back(field);
    if (fields.size() < 12) continue;
    RecordedPose pose;
    pose.camera_id = fields[0];
    pose.seq = std::stoull(fields[1]);
    pose.posed = fields[4] == "1";
    const Eigen::Quaterniond q(std::stod(fields[11]), std::stod(fields[8]), std::stod(fields[9]),
                               std::stod(fields[10]));
    pose.camera_to_world.linear() = q.normalized().toRotationMatrix();
    pose.camera_to_world.translation() =
        Eigen::Vector3d(std::stod(fields[5]), std::stod(fields[6]), std::stod(fields[7]));
    out.push_back(pose);
  }
  return out;
}

class TrackedCameras : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("semfuse_tracked_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(TrackedCameras, ASecondCameraWithoutPoseJoinsTheMapAndTheTrajectoryIsRecorded) {
  const dds_domainid_t domain = serverTestDomain();
  ServerHarness h(domain);
  // The recorder's reader exists before the server does (it writes the file's header once it
  // has), so the server's pose writer discovers it while starting, as it does the harness's: the
  // poses topic is volatile and a reader matched late would miss the first poses.
  const std::filesystem::path trajectory = dir_ / "poses.csv";
  ChildProcess recorder({SEMFUSE_QUERY_EXE, "--domain-id", std::to_string(domain), "--dds-profile", loopbackProfile(),
                         "--log-level", "warn", "poses", "--out", trajectory.string(), "--format", "csv",
                         "--include-lost"});
  ASSERT_TRUE(eventually([&] {
    return std::filesystem::exists(trajectory) && std::filesystem::file_size(trajectory) > 0;
  })) << "the pose recorder did not start";
  h.startServer({"--legend", "synthetic", "--voxel-size", std::to_string(kTrackedMapVoxel), "--truncation",
                 std::to_string(4 * kTrackedMapVoxel), "--autosave-period", "0", "--queue-per-camera", "64",
                 "--max-queue-wait", "0"});

  // Camera a maps 60 frames of the orbit from nothing (its first frame defines the world frame);
  // camera b then sees frames 20..49 of the same orbit, which a's keyframes show.
  const synthetic::SyntheticSequence a(sequenceConfig("a"));
  const synthetic::SyntheticSequence b(sequenceConfig("b"));
  struct Sent {
    const synthetic::SyntheticSequence* sequence;
    int index;
  };
  std::vector<Sent> plan;
  for (int i = 0; i < 60; ++i) plan.push_back({&a, i});
  for (int i = 20; i < 50; ++i) plan.push_back({&b, i});
  for (const Sent& sent : plan) {
    auto frame = sent.sequence->frame(sent.index, /*with_pose=*/false);
    ASSERT_TRUE(frame.ok()) << frame.error();
    auto encoded = wire::encodeFrame(frame.value());
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    ASSERT_TRUE(h.frames().write(encoded.value().msg()).ok());
    ASSERT_TRUE(h.waitPose(sent.sequence->config().camera_id, static_cast<uint64_t>(sent.index), 20s))
        << "no pose for " << sent.sequence->config().camera_id << "/" << sent.index;
  }

  // Every frame processed: integrated or lost, per camera.
  auto status = h.waitStatus(
      [](const semfuse_msg_dds__ServerStatus_& s) {
        uint64_t processed = 0;
        for (uint32_t i = 0; i < s.cameras._length; ++i)
          processed += s.cameras._buffer[i].frames_integrated + s.cameras._buffer[i].frames_lost;
        return processed >= 90;
      },
      10s);
  std::map<std::string, const semfuse_msg_dds__CameraState_*> cameras;
  for (uint32_t i = 0; i < status->cameras._length; ++i)
    cameras[status->cameras._buffer[i].camera_id] = &status->cameras._buffer[i];
  ASSERT_EQ(cameras.count("a"), 1u);
  ASSERT_EQ(cameras.count("b"), 1u);
  EXPECT_EQ(cameras["a"]->frames_integrated, 60u);
  EXPECT_EQ(cameras["a"]->frames_lost, 0u);
  // b's first frame proposes its pose from a keyframe, the second confirms it.
  EXPECT_GE(cameras["b"]->relocalisations, 1u);
  EXPECT_LE(cameras["b"]->frames_lost, 2u);
  EXPECT_GE(cameras["b"]->frames_integrated, 28u);
  EXPECT_EQ(counterOf(status->rejected, "first_frame_without_pose"), 0u);
  EXPECT_EQ(counterOf(status->dropped, "tracking_lost"), cameras["b"]->frames_lost);

  ASSERT_EQ(recorder.stop(SIGINT), 0);
  const std::vector<RecordedPose> recorded = readCsvTrajectory(trajectory);
  ASSERT_EQ(recorded.size(), plan.size()) << "every pose the server published is in the file";
  // The world frame is camera a's first pose: every integrated pose, of both cameras, must be the
  // true pose in that frame.
  const Pose world_from_synthetic = a.pose(0).inverse();
  std::map<std::string, int> integrated;
  for (const RecordedPose& pose : recorded) {
    if (!pose.posed) continue;
    ++integrated[pose.camera_id];
    const Pose truth = world_from_synthetic * a.pose(static_cast<int>(pose.seq));
    const Pose error = truth.inverse() * pose.camera_to_world;
    EXPECT_LT(error.translation().norm(), 0.02) << pose.camera_id << "/" << pose.seq;
    EXPECT_LT(Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI, 1.0) << pose.camera_id << "/" << pose.seq;
  }
  EXPECT_EQ(integrated["a"], 60);
  EXPECT_EQ(static_cast<uint64_t>(integrated["b"]), cameras["b"]->frames_integrated);
}

}  // namespace
