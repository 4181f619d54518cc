// semfuse against Fast DDS, a DDS implementation it did not write. The peer (fastdds/) is
// configured and built here, at test time, with type support fastddsgen generates from the
// ROS 2 IDL. It streams the synthetic room as a ROS 2 camera driver would (sensor_msgs depth
// 16UC1 + rgb8 colour + CameraInfo, sensor-data QoS, poses on /tf); semfuse-server --ros-ingest
// must integrate it into a map whose geometry (and, with ground-truth segmentations, labels)
// match the scene, and the peer must receive the server's /tf poses and status.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <future>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "../server/server_harness.hpp"
#include "interop_support.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

constexpr int kFrames = 30;
constexpr double kRateHz = 10.0;
constexpr double kVoxel = 0.02;
const fs::path kPeerBuild = fs::path(SEMFUSE_BINARY_DIR) / "tests/interop/fastdds_peer_build";

// Builds the Fast DDS peer once per run (configure + build, output in a log).
std::string buildPeer() {
  const std::string cmake = SEMFUSE_CMAKE_COMMAND;
  const std::string configure =
      cmake + " -S " + std::string(SEMFUSE_SOURCE_DIR) + "/tests/interop/fastdds -B " + kPeerBuild.string() +
      " -DCMAKE_BUILD_TYPE=Release -DSEMFUSE_IDL_DIR=" + std::string(SEMFUSE_SOURCE_DIR) + "/idl";
  fs::create_directories(kPeerBuild);
  const fs::path log = kPeerBuild / "build.log", err = kPeerBuild / "build.err";
  if (runCommand(configure, log, err) != 0)
    return "configuring the peer failed:\n" + tail(readFile(log) + readFile(err));
  if (runCommand(cmake + " --build " + kPeerBuild.string() + " -j2", log, err) != 0)
    return "building the peer failed:\n" + tail(readFile(log) + readFile(err));
  return "";
}

struct TfLine {
  double t;
  std::string parent, child;
  Eigen::Vector3d translation;
  Eigen::Quaterniond rotation;
};

}  // namespace

TEST(FastDdsInterop, RosCameraOnFastDdsIsFusedAndHearsTfAndStatus) {
  if (std::string(SEMFUSE_FASTDDSGEN).empty()) {
    GTEST_SKIP() << "fastddsgen not found when semfuse was configured: install Debian packages fastddsgen, "
                    "libfastrtps-dev (deploy/install-deps.sh) and re-run cmake to run the Fast DDS interop test";
  }
  const std::string build_error = buildPeer();
  ASSERT_EQ(build_error, "");
  const fs::path peer = kPeerBuild / "fastdds_peer";
  ASSERT_TRUE(fs::exists(peer));

  const fs::path dir = fs::temp_directory_path() / ("semfuse_fastdds_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);  // 320x240
  config.trajectory.frame_count = kFrames;
  synthetic::SyntheticSequence sequence(config);
  writeFrameFolder(sequence, kFrames, dir / "frames");

  const int domain = interopDomain();
  ServerHarness h(domain);
  h.startServer({"--legend",
                 "synthetic",
                 "--voxel-size",
                 std::to_string(kVoxel),
                 "--truncation",
                 std::to_string(4 * kVoxel),
                 "--max-depth",
                 "8",
                 "--queue-per-camera",
                 "64",
                 "--max-queue-wait",
                 "0",
                 "--ros-ingest",
                 "--ros.camera-id",
                 "fastdds",
                 "--ros.world-frame",
                 "map",
                 "--ros.publish-tf",
                 "all",
                 "--ros.wait",
                 "1.0",
                 "--ros.pending-depth",
                 "64"});

  std::ostringstream command;
  command << peer << " --domain " << domain << " --frames " << (dir / "frames") << " --rate " << kRateHz
          << " --world-frame map --camera-frame camera_optical --expect-tf " << kFrames << " --expect-integrated "
          << kFrames << " --timeout 90";
  auto peer_run =
      std::async(std::launch::async, [&] { return runCommand(command.str(), dir / "peer.out", dir / "peer.err"); });

  // Each integrated frame's pose says which frame (by stamp) got which server seq: label those
  // with the ground truth through the native path, as a segmenter would.
  std::map<uint64_t, int> index_of_seq;
  for (uint64_t seq = 1; seq <= static_cast<uint64_t>(kFrames); ++seq) {
    auto pose = h.waitPose("fastdds", seq, 60s);
    ASSERT_TRUE(pose) << "no pose for ROS frame " << seq << "\npeer: " << tail(readFile(dir / "peer.err"));
    EXPECT_TRUE((*pose)->posed);
    const double t = (*pose)->header.stamp.sec + (*pose)->header.stamp.nanosec * 1e-9;
    const int index = static_cast<int>(std::lround((t - 1000.0) * kRateHz));
    ASSERT_TRUE(index >= 0 && index < kFrames) << "stamp " << t;
    // The pose tf gave is the pose the frame was rendered at.
    const Eigen::Matrix4d expected = sequence.pose(index).matrix();
    const Pose used = wire::poseFromRowMajor((*pose)->camera_to_world);
    EXPECT_LT((used.matrix() - expected).cwiseAbs().maxCoeff(), 1e-6) << "frame " << index;
    index_of_seq[seq] = index;
    auto truth = sequence.groundTruth(index);
    ASSERT_TRUE(truth.ok());
    Segmentation segmentation = truth.value();
    segmentation.camera_id = "fastdds";
    segmentation.frame_seq = seq;
    auto encoded = wire::encodeSegmentation(segmentation);
    ASSERT_TRUE(encoded.ok()) << encoded.error();
    ASSERT_TRUE(h.segmentations().write(encoded.value().msg()).ok());
  }

  const int peer_code = peer_run.get();
  const std::string peer_out = readFile(dir / "peer.out");
  ASSERT_EQ(peer_code, 0) << "peer stderr:\n" << tail(readFile(dir / "peer.err")) << "\nstdout:\n" << tail(peer_out);

  auto status = h.waitStatus([](const auto& s) { return s.segmentations_integrated == kFrames; }, 30s);
  ASSERT_NE(status.get(), nullptr);
  EXPECT_EQ(status->frames_received, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(status->frames_integrated, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(status->segmentations_integrated, static_cast<uint64_t>(kFrames));
  EXPECT_EQ(counterTotal(status->dropped), 0u);
  EXPECT_EQ(counterTotal(status->rejected), 0u);
  // The decode stage counts each image of a ROS frame: its depth and its colour.
  const semfuse_msg_dds__StageTiming_* decode = nullptr;
  for (uint32_t i = 0; i < status->stages._length; ++i)
    if (std::string(status->stages._buffer[i].stage) == "frame_decode") decode = &status->stages._buffer[i];
  ASSERT_NE(decode, nullptr);
  EXPECT_EQ(decode->count, static_cast<uint64_t>(2 * kFrames));
  EXPECT_GT(decode->max_ms, 0.0F);

  // The peer heard the server on /tf (world -> camera at each frame's stamp, the pose it sent)
  // and on /semfuse/status (all frames integrated).
  std::istringstream lines(peer_out);
  std::string line;
  int tf_count = 0, status_count = 0;
  uint64_t last_integrated = 0;
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string kind;
    in >> kind;
    if (kind == "TF") {
      int32_t sec;
      uint32_t nsec;
      TfLine tf;
      in >> sec >> nsec >> tf.parent >> tf.child >> tf.translation.x() >> tf.translation.y() >> tf.translation.z() >>
          tf.rotation.x() >> tf.rotation.y() >> tf.rotation.z() >> tf.rotation.w();
      ASSERT_TRUE(in) << line;
      EXPECT_EQ(tf.parent, "map");
      EXPECT_EQ(tf.child, "camera_optical");
      const int index = static_cast<int>(std::lround((sec + nsec * 1e-9 - 1000.0) * kRateHz));
      ASSERT_TRUE(index >= 0 && index < kFrames) << line;
      const Pose truth = sequence.pose(index);
      EXPECT_LT((tf.translation - truth.translation()).norm(), 1e-6) << line;
      EXPECT_LT(tf.rotation.angularDistance(Eigen::Quaterniond(truth.rotation())), 1e-6) << line;
      ++tf_count;
    } else if (kind == "STATUS") {
      uint64_t received;
      in >> received >> last_integrated;
      ++status_count;
    }
  }
  EXPECT_EQ(tf_count, kFrames);
  EXPECT_GE(status_count, 1);
  EXPECT_EQ(last_integrated, static_cast<uint64_t>(kFrames));

  // The map: raycast between two frames; depth and labels against the scene.
  const Pose view = sequence.config().trajectory.pose(12.5);
  const PinholeIntrinsics& k = sequence.config().intrinsics;
  semfuse_srv_dds__Raycast_Request_ request{};
  wire::poseToRowMajor(view, request.camera_to_world);
  request.intrinsics = {static_cast<uint32_t>(k.width), static_cast<uint32_t>(k.height), k.fx, k.fy, k.cx, k.cy};
  request.layers =
      semfuse_srv_dds__Raycast_Request_Constants_LAYER_DEPTH | semfuse_srv_dds__Raycast_Request_Constants_LAYER_LABELS;
  auto reply = h.raycast().call(request, 30s);
  ASSERT_TRUE(reply.ok()) << reply.error();
  ASSERT_EQ(reply.value()->status, 0) << dds::replyMessage(*reply.value());
  auto depth = wire::imageToMat(reply.value()->depth);
  auto labels = wire::imageToMat(reply.value()->labels);
  ASSERT_TRUE(depth.ok() && labels.ok());
  auto truth = synthetic::renderView(sequence.scene(), k, view);
  ASSERT_TRUE(truth.ok());
  int both = 0, depth_close = 0, labeled = 0, label_agree = 0;
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u) {
      const float expected = truth.value().depth.at<float>(v, u), got = depth.value().at<float>(v, u);
      if (!(expected > 0) || !std::isfinite(got)) continue;
      ++both;
      depth_close += std::abs(expected - got) < 0.02f;
      const uint16_t want = truth.value().labels.at<uint16_t>(v, u), have = labels.value().at<uint16_t>(v, u);
      if (want == 0 || have == 0) continue;
      ++labeled;
      label_agree += want == have;
    }
  std::printf("raycast at frame 12.5: %d pixels with depth, %.1f%% within 2 cm; %.1f%% of %d labeled pixels right\n",
              both, 100.0 * depth_close / std::max(both, 1), 100.0 * label_agree / std::max(labeled, 1), labeled);
  ASSERT_GT(both, k.width * k.height / 2) << "the map covers too little of the view";
  EXPECT_GE(static_cast<double>(depth_close) / both, 0.95) << depth_close << " of " << both;
  ASSERT_GT(labeled, both / 2);
  EXPECT_GE(static_cast<double>(label_agree) / labeled, 0.95) << label_agree << " of " << labeled;

  EXPECT_EQ(h.stopServer(), 0);
  fs::remove_all(dir);
}
