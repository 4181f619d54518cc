// semfuse-server's ROS 2 input reading compressed depth (compressed_depth_image_transport's
// format) over loopback DDS: RVL and PNG depth of the synthetic room are fused, a cut RVL image
// is rejected and counted with its reason, and the server keeps going.
#include <atomic>
#include <thread>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/synthetic/synthetic_sequence.hpp"
#include "semfuse/wire/image_convert.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "sensor_msgs.h"
#include "server_harness.hpp"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;

namespace {

constexpr const char* kCompressedDepthTopic = "/camera/depth/image_raw/compressedDepth";

TEST(RosCompressedDepthEndToEnd, RvlAndPngDepthAreFusedAndABrokenOneIsCounted) {
  ServerHarness h(serverTestDomain());
  h.startServer({"--legend", "synthetic", "--voxel-size", "0.02", "--truncation", "0.08", "--ros-ingest",
                 "--ros.camera-id", "ros-depth", "--ros.compressed-depth-topic", kCompressedDepthTopic,
                 "--ros.color-topic", "", "--ros.use-tf", "false", "--ros.wait", "5"});
  const auto& p = h.participant();
  dds::Topic<sensor_msgs_msg_dds__CameraInfo_> info_topic(p, "rt/camera/depth/camera_info");
  dds::Topic<sensor_msgs_msg_dds__CompressedImage_> depth_topic(p, std::string("rt") + kCompressedDepthTopic);
  dds::Writer<sensor_msgs_msg_dds__CameraInfo_> info(info_topic, dds::qos::sensorData());
  dds::Writer<sensor_msgs_msg_dds__CompressedImage_> depth(depth_topic, dds::qos::sensorData());
  ASSERT_TRUE(info.waitForReaders(1, DDS_SECS(30)));
  ASSERT_TRUE(depth.waitForReaders(1, DDS_SECS(30)));

  synthetic::SequenceConfig config;
  config.intrinsics = config.intrinsics.scaled(0.5);  // 320x240 keeps the test quick
  config.trajectory.frame_count = 300;  // 1.2 degrees and 3.4 cm of orbit per frame: tracked from the last
  synthetic::SyntheticSequence sequence(config);
  auto millimetresOf = [&](int index) {
    auto frame = sequence.frame(index);
    EXPECT_TRUE(frame.ok());
    return wire::depthMetresToUnits(frame.value().depth, 0.001);
  };
  const Stamp stamp{1700000000, 0};
  // The CameraInfo comes again and again, as from a camera driver: a best-effort sample written
  // before the server's reader has matched this writer is lost, and a depth image waits for one.
  const auto camera_info = wire::cameraInfoFromIntrinsics(config.intrinsics, stamp, "depth_optical");
  std::atomic<bool> sending_info{true};
  std::thread info_sender([&] {
    while (sending_info) {
      (void)info.write(camera_info.msg());
      std::this_thread::sleep_for(20ms);
    }
  });
  struct StopSending {
    std::atomic<bool>& flag;
    std::thread& thread;
    ~StopSending() {
      flag = false;
      thread.join();
    }
  } stop_sending{sending_info, info_sender};

  // Each depth image is the server's next ROS frame (1, 2, ...); its pose says it was fused.
  auto send = [&](const std::string& compression, int index, uint32_t nanosec, uint32_t cut_bytes = 0) {
    auto owned =
        wire::compressedDepthFromMillimetres(millimetresOf(index), compression, {stamp.sec, nanosec}, "depth_optical");
    ASSERT_TRUE(owned.ok()) << owned.error();
    owned.value().msg().data._length -= cut_bytes;
    ASSERT_TRUE(depth.write(owned.value().msg()).ok());
  };
  send("rvl", 0, 0);
  auto first = h.waitPose("ros-depth", 1, 30s);
  ASSERT_TRUE(first) << "the RVL depth image was not fused";
  EXPECT_TRUE((*first)->posed);
  send("png", 1, 33000000);
  auto second = h.waitPose("ros-depth", 2, 30s);
  ASSERT_TRUE(second) << "the PNG depth image was not fused";
  EXPECT_TRUE((*second)->posed);

  send("rvl", 2, 66000000, 8);  // the last two words of the stream are missing
  auto rejected = h.waitStatus([](const auto& s) { return counterOf(s.rejected, "invalid_frame") >= 1; }, 30s);
  ASSERT_NE(rejected.get(), nullptr);
  std::string errors;
  for (uint32_t i = 0; i < rejected->last_errors._length; ++i)
    errors += std::string(rejected->last_errors._buffer[i].message) + "\n";
  EXPECT_NE(errors.find("compressed depth: RVL payload ends at pixel "), std::string::npos) << errors;

  send("rvl", 3, 99000000);
  auto fourth = h.waitPose("ros-depth", 4, 30s);
  ASSERT_TRUE(fourth) << "the server stopped fusing after the bad image";
  EXPECT_TRUE((*fourth)->posed);
  // Each posed frame is integrated, or skipped when a newer one was tracked before its turn.
  auto status = h.waitStatus([](const auto& s) { return s.frames_integrated + s.frames_skipped >= 3; }, 30s);
  ASSERT_NE(status.get(), nullptr);
  EXPECT_EQ(status->frames_received, 4u);
  EXPECT_EQ(status->frames_posed, 3u);
  EXPECT_GE(status->frames_integrated, 1u);
  EXPECT_EQ(counterOf(status->rejected, "invalid_frame"), 1u);
  EXPECT_EQ(counterTotal(status->dropped), 0u);
  EXPECT_GE(status->allocated_voxels, 1000u);
  EXPECT_EQ(h.stopServer(), 0);
}

}  // namespace
