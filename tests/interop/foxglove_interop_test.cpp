// semfuse's CDR against an independent serializer: foxglove's @foxglove/rosmsg2-serialization
// (npm), reading standard ROS 2 types from @foxglove/rosmsg-msgs-common and semfuse's own from
// the .msg files of idl/ros2/semfuse_msgs. Each message is written as a flat field list, encoded
// by foxglove, decoded by Cyclone field for field, re-encoded by Cyclone and decoded by foxglove
// back to the same fields; foxglove's bytes are also injected into a running server, which must
// decode and use them (a ROS camera frame at the tf pose, a native frame).
#include <cmath>
#include <cstring>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "../server/server_harness.hpp"
#include "interop_support.hpp"
#include "nav_msgs.h"
#include "semfuse/dds/raw.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/ros_visualization.hpp"
#include "sensor_msgs.h"
#include "tf2_msgs.h"
#include "visualization_msgs.h"

using namespace semfuse;
using namespace semfuse::testing;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

const fs::path kNodeDir = fs::path(SEMFUSE_BINARY_DIR) / "tests/interop/foxglove_node";
const fs::path kSourceDir = fs::path(SEMFUSE_SOURCE_DIR) / "tests/interop/foxglove";
const fs::path kMsgDir = fs::path(SEMFUSE_SOURCE_DIR) / "idl/ros2/semfuse_msgs/msg";

using Flat = std::map<std::string, std::string>;

// path=value lines; a numeric array `path=[1,2]` becomes path.length=2, path[0]=1, path[1]=2,
// the way foxglove's side prints arrays.
Flat parseFlat(const std::string& text) {
  Flat flat;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string path = line.substr(0, eq), value = line.substr(eq + 1);
    if (value.size() < 2 || value.front() != '[') {
      flat[path] = value;
      continue;
    }
    std::istringstream items(value.substr(1, value.size() - 2));
    std::string item;
    size_t n = 0;
    while (std::getline(items, item, ',')) flat[path + "[" + std::to_string(n++) + "]"] = item;
    flat[path + ".length"] = std::to_string(n);
  }
  return flat;
}

// Equal as numbers when both are numbers (foxglove prints float32 values widened to double),
// else as text.
bool sameValue(const std::string& a, const std::string& b) {
  char *end_a = nullptr, *end_b = nullptr;
  const double x = std::strtod(a.c_str(), &end_a), y = std::strtod(b.c_str(), &end_b);
  if (!a.empty() && !b.empty() && *end_a == '\0' && *end_b == '\0') {
    return x == y || static_cast<float>(x) == static_cast<float>(y);
  }
  return a == b;
}

class FoxgloveInterop : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // npm ci into the build tree, from the committed lockfile, once per build directory. Each test
    // is a process of its own and ctest may start two at once (RESOURCE_LOCK did not keep them
    // apart in a CI run: both ran `npm ci`, and one failed removing what the other wrote), so the
    // install runs under a file lock and is skipped by whoever comes second. The marker is written
    // once npm ci has finished, so a test never starts on half the modules.
    const fs::path marker = kNodeDir / "npm-ci.done";
    if (fs::exists(marker)) return;
    fs::create_directories(kNodeDir);
    const std::string install = "test -f '" + marker.string() + "' || { cp '" + (kSourceDir / "package.json").string() +
                                "' '" + (kSourceDir / "package-lock.json").string() + "' '" + kNodeDir.string() +
                                "/' && npm ci --no-audit --no-fund --prefix '" + kNodeDir.string() + "' && touch '" +
                                marker.string() + "'; }";
    const int code = runCommand("flock '" + (kNodeDir / "npm.lock").string() + "' sh -c \"" + install + "\"",
                                kNodeDir / "npm.out", kNodeDir / "npm.err");
    setup_error_ =
        code == 0 ? "" : "npm ci failed (npm's registry must be reachable):\n" + tail(readFile(kNodeDir / "npm.err"));
  }

  void SetUp() override {
    ASSERT_EQ(setup_error_, "");
    dir_ = fs::temp_directory_path() / ("semfuse_foxglove_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // foxglove's bytes for `flat` as a `type`.
  std::vector<uint8_t> foxgloveEncode(const std::string& type, const std::string& flat) {
    const fs::path in = dir_ / "in.flat", out = dir_ / "out.cdr";
    std::ofstream(in) << flat;
    const int code = runCommand(node(" encode " + type + " " + in.string() + " " + out.string()), dir_ / "node.out",
                                dir_ / "node.err");
    EXPECT_EQ(code, 0) << readFile(dir_ / "node.err");
    const std::string bytes = readFile(out);
    return {bytes.begin(), bytes.end()};
  }

  // foxglove's reading of `bytes` as a `type`.
  Flat foxgloveDecode(const std::string& type, const std::vector<uint8_t>& bytes) {
    const fs::path in = dir_ / "in.cdr", out = dir_ / "out.flat";
    std::ofstream(in, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    const int code = runCommand(node(" decode " + type + " " + in.string() + " " + out.string()), dir_ / "node.out",
                                dir_ / "node.err");
    EXPECT_EQ(code, 0) << readFile(dir_ / "node.err");
    return parseFlat(readFile(out));
  }

  // Every field of `expected` read back by foxglove with the same value.
  void expectFoxgloveReads(const std::string& type, const std::vector<uint8_t>& bytes, const std::string& expected) {
    const Flat got = foxgloveDecode(type, bytes);
    for (const auto& [path, value] : parseFlat(expected)) {
      const auto it = got.find(path);
      if (it == got.end()) {
        ADD_FAILURE() << type << ": foxglove read no field " << path;
        continue;
      }
      EXPECT_TRUE(sameValue(it->second, value))
          << type << "." << path << ": foxglove read " << it->second << ", semfuse wrote " << value;
    }
  }

  // The full cycle for one message: foxglove -> Cyclone (checked by `check`) -> foxglove.
  template <class T, class Check>
  void roundTrip(const std::string& type, const std::string& flat, Check check) {
    const std::vector<uint8_t> foxglove = foxgloveEncode(type, flat);
    ASSERT_GT(foxglove.size(), 4u);
    auto decoded = dds::deserialize<T>(foxglove);
    ASSERT_TRUE(decoded.ok()) << type << ": " << decoded.error();
    check(*decoded.value());
    const std::vector<uint8_t> ours = dds::serialize(*decoded.value());
    // Same body. Cyclone pads the sample to a multiple of 4 bytes and says how many padding
    // bytes it added in the low bits of the encapsulation options; foxglove does not pad.
    const size_t padding = ours[3] & 3u;
    ASSERT_EQ(ours.size() - padding, foxglove.size()) << type;
    EXPECT_TRUE(std::equal(foxglove.begin() + 4, foxglove.end(), ours.begin() + 4)) << type << ": CDR bodies differ";
    expectFoxgloveReads(type, ours, flat);
  }

  static std::string node(const std::string& args) {
    return "NODE_PATH=" + (kNodeDir / "node_modules").string() + " node " + (kSourceDir / "rosmsg_cdr.mjs").string() +
           args + " --msg-dir " + kMsgDir.string();
  }

  static inline std::string setup_error_;
  fs::path dir_;
};

const char* kDepthImage =
    "header.stamp.sec=1700000000\nheader.stamp.nanosec=123456789\nheader.frame_id=\"camera_optical\"\n"
    "height=2\nwidth=3\nencoding=\"16UC1\"\nis_bigendian=0\nstep=6\n"
    "data=[232,3,208,7,184,11,160,15,136,19,112,23]\n";  // 1000..6000 mm

const char* kCameraInfo =
    "header.stamp.sec=1700000000\nheader.stamp.nanosec=123456789\nheader.frame_id=\"camera_optical\"\n"
    "height=48\nwidth=64\ndistortion_model=\"plumb_bob\"\nd=[0.1,-0.2,0.001,0.002,0.03]\n"
    "k=[50.5,0,31.5,0,51.25,23.5,0,0,1]\nr=[1,0,0,0,1,0,0,0,1]\np=[50.5,0,31.5,0,0,51.25,23.5,0,0,0,1,0]\n"
    "binning_x=1\nbinning_y=2\nroi.x_offset=3\nroi.y_offset=4\nroi.height=5\nroi.width=6\nroi.do_rectify=true\n";

const char* kTf =
    "transforms[0].header.stamp.sec=1700000000\ntransforms[0].header.stamp.nanosec=123456789\n"
    "transforms[0].header.frame_id=\"map\"\ntransforms[0].child_frame_id=\"camera_optical\"\n"
    "transforms[0].transform.translation.x=0.5\ntransforms[0].transform.translation.y=-1.25\n"
    "transforms[0].transform.translation.z=1.5\ntransforms[0].transform.rotation.x=0\n"
    "transforms[0].transform.rotation.y=0\ntransforms[0].transform.rotation.z=0.7071067811865476\n"
    "transforms[0].transform.rotation.w=0.7071067811865476\n"
    "transforms[1].header.stamp.sec=1\ntransforms[1].header.stamp.nanosec=2\ntransforms[1].header.frame_id=\"odom\"\n"
    "transforms[1].child_frame_id=\"base_link\"\ntransforms[1].transform.translation.x=7\n"
    "transforms[1].transform.translation.y=8\ntransforms[1].transform.translation.z=9\n"
    "transforms[1].transform.rotation.x=0\ntransforms[1].transform.rotation.y=0\n"
    "transforms[1].transform.rotation.z=0\ntransforms[1].transform.rotation.w=1\n";

const char* kFrame =
    "header.stamp.sec=42\nheader.stamp.nanosec=500000000\nheader.frame_id=\"world\"\ncamera_id=\"fox\"\n"
    "seq=18446744073709551615\nintrinsics.width=2\nintrinsics.height=1\nintrinsics.fx=525.5\nintrinsics.fy=524.25\n"
    "intrinsics.cx=0.5\nintrinsics.cy=0.25\ndepth_encoding=\"16UC1\"\ndepth_scale=0.001\ndepth=[208,7,0,0]\n"
    "color_encoding=\"rgb8\"\ncolor=[255,0,0,0,128,255]\nhas_pose=true\n"
    "camera_to_world=[1,0,0,0.1,0,1,0,0.2,0,0,1,0.3]\n";

const char* kStatus =
    "header.stamp.sec=9\nheader.stamp.nanosec=10\nheader.frame_id=\"\"\nserver_id=\"semfuse\"\nversion=\"0.1.0\"\n"
    "uptime_s=12.5\nframes_received=100\nframes_integrated=97\nframes_lost=1\nsegmentations_received=50\n"
    "segmentations_integrated=49\ndropped[0].reason=\"queue_full\"\ndropped[0].camera_id=\"cam0\"\ndropped[0].count=2\n"
    "dropped[1].reason=\"ros_no_tf\"\ndropped[1].camera_id=\"ros\"\ndropped[1].count=5000000000\n"
    "rejected[0].reason=\"invalid_frame\"\nrejected[0].camera_id=\"cam1\"\nrejected[0].count=3\nqueued_frames=4\n"
    "pending_segmentations=5\nhistory_frames=6\nvoxel_size=0.01\ntruncation=0.04\nallocated_voxels=123456789012\n"
    "allocated_blocks=7\nmap_bytes=8\nrss_bytes=9\ncameras[0].camera_id=\"cam0\"\ncameras[0].tracking_state=1\n"
    "cameras[0].last_seq=99\ncameras[0].frames_received=100\ncameras[0].frames_integrated=97\ncameras[0].frames_lost="
    "1\n"
    "cameras[0].frame_rate_hz=29.5\ncameras[0].last_frame_age_s=0.25\ncameras[0].stale=false\n"
    "cameras[0].lost_reason=\"too few inliers\"\ncameras[0].frames_since_lost=3\ncameras[0].relocalisations=2\n"
    "last_errors[0].stamp.sec=3\nlast_errors[0].stamp.nanosec=4\nlast_errors[0].source=\"ingest\"\n"
    "last_errors[0].message=\"depth: unknown encoding 'rgb16'\"\nmap_file=\"/tmp/map.vdb\"\nlast_save_ok=true\n"
    "last_save_age_s=1.5\nstages[0].stage=\"frame_decode\"\nstages[0].count=100\nstages[0].p50_ms=2.5\n"
    "stages[0].p95_ms=4.25\nstages[0].max_ms=11\nmap_revision=12000000000\ndistance_field_revision=11\n"
    "snapshot_bytes=140000000\n";

// What rt/semfuse/occupancy carries.
const char* kOccupancyGrid =
    "header.stamp.sec=1700000000\nheader.stamp.nanosec=5\nheader.frame_id=\"map\"\ninfo.map_load_time.sec=1700000000\n"
    "info.map_load_time.nanosec=5\ninfo.resolution=0.05000000074505806\ninfo.width=3\ninfo.height=2\n"
    "info.origin.position.x=-1.25\ninfo.origin.position.y=2.5\ninfo.origin.position.z=0.375\n"
    "info.origin.orientation.x=0\ninfo.origin.orientation.y=0\ninfo.origin.orientation.z=0\n"
    "info.origin.orientation.w=1\ndata=[0,100,-1,99,0,0]\n";

std::string str(const char* s) { return s ? s : ""; }

TEST_F(FoxgloveInterop, StandardRosMessagesAgreeFieldForField) {
  roundTrip<sensor_msgs_msg_dds__Image_>("sensor_msgs/Image", kDepthImage, [](const sensor_msgs_msg_dds__Image_& m) {
    EXPECT_EQ(m.header.stamp.sec, 1700000000);
    EXPECT_EQ(m.header.stamp.nanosec, 123456789u);
    EXPECT_EQ(str(m.header.frame_id), "camera_optical");
    EXPECT_EQ(m.height, 2u);
    EXPECT_EQ(m.width, 3u);
    EXPECT_EQ(str(m.encoding), "16UC1");
    EXPECT_EQ(m.step, 6u);
    auto depth = wire::depthImageToMetres(m);
    ASSERT_TRUE(depth.ok()) << depth.error();
    EXPECT_FLOAT_EQ(depth.value().at<float>(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(depth.value().at<float>(1, 2), 6.0f);
  });
  roundTrip<sensor_msgs_msg_dds__CameraInfo_>("sensor_msgs/CameraInfo", kCameraInfo,
                                              [](const sensor_msgs_msg_dds__CameraInfo_& m) {
                                                EXPECT_EQ(m.width, 64u);
                                                EXPECT_EQ(str(m.distortion_model), "plumb_bob");
                                                ASSERT_EQ(m.d._length, 5u);
                                                EXPECT_EQ(m.d._buffer[1], -0.2);
                                                EXPECT_EQ(m.p[6], 23.5);
                                                EXPECT_EQ(m.binning_y, 2u);
                                                EXPECT_EQ(m.roi.width, 6u);
                                                EXPECT_TRUE(m.roi.do_rectify);
                                                auto k = wire::intrinsicsFromCameraInfo(m);
                                                ASSERT_TRUE(k.ok()) << k.error();
                                                EXPECT_EQ(k.value().fx, 50.5);
                                                EXPECT_EQ(k.value().fy, 51.25);
                                                EXPECT_EQ(k.value().cx, 31.5);
                                                EXPECT_EQ(k.value().cy, 23.5);
                                              });
  roundTrip<tf2_msgs_msg_dds__TFMessage_>("tf2_msgs/TFMessage", kTf, [](const tf2_msgs_msg_dds__TFMessage_& m) {
    ASSERT_EQ(m.transforms._length, 2u);
    const auto& t = m.transforms._buffer[0];
    EXPECT_EQ(str(t.header.frame_id), "map");
    EXPECT_EQ(str(t.child_frame_id), "camera_optical");
    auto pose = wire::poseFromTransform(t.transform);
    ASSERT_TRUE(pose.ok()) << pose.error();
    EXPECT_NEAR(pose.value().linear()(1, 0), 1.0, 1e-12);  // 90 degrees about z
    EXPECT_EQ(pose.value().translation().y(), -1.25);
    EXPECT_EQ(str(m.transforms._buffer[1].child_frame_id), "base_link");
    EXPECT_EQ(m.transforms._buffer[1].transform.translation.z, 9.0);
  });
}

TEST_F(FoxgloveInterop, OccupancyGridAgreesFieldForField) {
  roundTrip<nav_msgs_msg_dds__OccupancyGrid_>(
      "nav_msgs/OccupancyGrid", kOccupancyGrid, [](const nav_msgs_msg_dds__OccupancyGrid_& m) {
        EXPECT_EQ(str(m.header.frame_id), "map");
        EXPECT_EQ(m.info.width, 3u);
        EXPECT_EQ(m.info.height, 2u);
        EXPECT_FLOAT_EQ(m.info.resolution, 0.05f);
        EXPECT_EQ(m.info.origin.position.x, -1.25);
        auto grid = wire::decodeOccupancyGrid(m);
        ASSERT_TRUE(grid.ok()) << grid.error();
        EXPECT_EQ(grid.value().cells, (std::vector<int8_t>{0, 100, -1, 99, 0, 0}));
        EXPECT_EQ(grid.value().z, 0.375);
      });
}

TEST_F(FoxgloveInterop, SemfuseMessagesFromTheMsgFilesAgreeFieldForField) {
  roundTrip<semfuse_msg_dds__Frame_>("semfuse/Frame", kFrame, [](const semfuse_msg_dds__Frame_& m) {
    EXPECT_EQ(m.seq, 18446744073709551615ull);
    EXPECT_EQ(str(m.camera_id), "fox");
    EXPECT_EQ(m.intrinsics.fy, 524.25);
    EXPECT_FLOAT_EQ(m.depth_scale, 0.001f);
    EXPECT_TRUE(m.has_pose);
    EXPECT_EQ(m.camera_to_world[11], 0.3);
    auto frame = wire::decodeFrame(m);
    ASSERT_TRUE(frame.ok()) << frame.error();
    EXPECT_FLOAT_EQ(frame.value().depth.at<float>(0, 0), 2.0f);
    EXPECT_EQ(frame.value().color.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 128, 255));
  });
  roundTrip<semfuse_msg_dds__ServerStatus_>(
      "semfuse/ServerStatus", kStatus, [](const semfuse_msg_dds__ServerStatus_& m) {
        EXPECT_EQ(m.frames_integrated, 97u);
        ASSERT_EQ(m.dropped._length, 2u);
        EXPECT_EQ(str(m.dropped._buffer[1].reason), "ros_no_tf");
        EXPECT_EQ(m.dropped._buffer[1].count, 5000000000ull);
        ASSERT_EQ(m.cameras._length, 1u);
        EXPECT_EQ(m.cameras._buffer[0].tracking_state, 1);
        EXPECT_FLOAT_EQ(m.cameras._buffer[0].frame_rate_hz, 29.5f);
        EXPECT_EQ(str(m.cameras._buffer[0].lost_reason), "too few inliers");
        EXPECT_EQ(m.cameras._buffer[0].frames_since_lost, 3u);
        EXPECT_EQ(m.cameras._buffer[0].relocalisations, 2u);
        ASSERT_EQ(m.last_errors._length, 1u);
        EXPECT_EQ(str(m.last_errors._buffer[0].message), "depth: unknown encoding 'rgb16'");
        EXPECT_EQ(m.allocated_voxels, 123456789012ull);
        EXPECT_EQ(m.last_save_age_s, 1.5);
        ASSERT_EQ(m.stages._length, 1u);
        EXPECT_EQ(str(m.stages._buffer[0].stage), "frame_decode");
        EXPECT_EQ(m.stages._buffer[0].count, 100u);
        EXPECT_FLOAT_EQ(m.stages._buffer[0].p95_ms, 4.25f);
        EXPECT_EQ(m.map_revision, 12000000000ull);
        EXPECT_EQ(m.distance_field_revision, 11u);
        EXPECT_EQ(m.snapshot_bytes, 140000000u);
      });
}

// Messages built by semfuse's own encoders (not from foxglove's bytes) read by foxglove.
TEST_F(FoxgloveInterop, FoxgloveReadsWhatSemfuseEncodes) {
  TrackedPose pose;
  pose.camera_id = "cam7";
  pose.seq = 77;
  pose.stamp = {5, 6};
  pose.frame_id = "world";
  pose.state = PoseState::kTracked;
  pose.posed = true;
  pose.camera_to_world.translation() = Eigen::Vector3d(1.5, -2.0, 0.25);
  pose.inlier_ratio = 0.75f;
  pose.iterations = 12;
  auto encoded_pose = wire::encodeTrackedPose(pose);
  expectFoxgloveReads("semfuse/TrackedPose", dds::serialize(encoded_pose.msg()),
                      "header.stamp.sec=5\nheader.stamp.nanosec=6\nheader.frame_id=\"world\"\ncamera_id=\"cam7\"\n"
                      "seq=77\nstate=1\nposed=true\ncamera_to_world.length=12\ncamera_to_world[3]=1.5\n"
                      "camera_to_world[7]=-2\ncamera_to_world[11]=0.25\ncamera_to_world[0]=1\ninlier_ratio=0.75\n"
                      "iterations=12\n");

  cv::Mat bgr(1, 2, CV_8UC3);
  bgr.at<cv::Vec3b>(0, 0) = {1, 2, 3};
  bgr.at<cv::Vec3b>(0, 1) = {4, 5, 6};
  auto image = wire::matToImage(bgr, "bgr8", {7, 8}, "cam");  // input is RGB: bgr8 swaps to 3,2,1
  ASSERT_TRUE(image.ok()) << image.error();
  expectFoxgloveReads("sensor_msgs/Image", dds::serialize(image.value().msg()),
                      "header.frame_id=\"cam\"\nheight=1\nwidth=2\nencoding=\"bgr8\"\nstep=6\ndata.length=6\n"
                      "data[0]=3\ndata[1]=2\ndata[2]=1\ndata[3]=6\n");

  auto info = wire::cameraInfoFromIntrinsics({640, 480, 525.0, 526.0, 319.5, 239.5}, {1, 2}, "cam");
  expectFoxgloveReads("sensor_msgs/CameraInfo", dds::serialize(info.msg()),
                      "width=640\nheight=480\nk[0]=525\nk[2]=319.5\nk[4]=526\nk[5]=239.5\nk[8]=1\np[0]=525\n"
                      "p[6]=239.5\np[10]=1\nr[0]=1\nr[4]=1\n");

  Pose camera = Pose::Identity();
  camera.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  camera.translation() = Eigen::Vector3d(1, 2, 3);
  auto transform = wire::transformFromPose(camera, {11, 12}, "map", "camera_optical");
  tf2_msgs_msg_dds__TFMessage_ tf{};
  tf.transforms._buffer = &transform.msg();
  tf.transforms._length = tf.transforms._maximum = 1;
  expectFoxgloveReads("tf2_msgs/TFMessage", dds::serialize(tf),
                      "transforms.length=1\ntransforms[0].header.frame_id=\"map\"\ntransforms[0].header.stamp.sec=11\n"
                      "transforms[0].child_frame_id=\"camera_optical\"\ntransforms[0].transform.translation.z=3\n"
                      "transforms[0].transform.rotation.z=0.7071067811865476\n"
                      "transforms[0].transform.rotation.w=0.7071067811865476\n");

  LabelLegend legend;
  legend.name = "tiny";
  legend.labels.push_back({3, "chair", {10, 20, 30}});
  legend.background_ids = {1};
  auto encoded_legend = wire::encodeLegend(legend, {1, 0});
  expectFoxgloveReads("semfuse/LabelLegend", dds::serialize(encoded_legend.msg()),
                      "name=\"tiny\"\nlabels.length=1\nlabels[0].id=3\nlabels[0].name=\"chair\"\nlabels[0].r=10\n"
                      "labels[0].g=20\nlabels[0].b=30\nbackground_ids.length=1\nbackground_ids[0]=1\n");
}

// The live mesh as RViz and Foxglove read it: a block's TRIANGLE_LIST marker in a MarkerArray
// and the surface cloud with its label field, built by semfuse's encoders, read by foxglove.
TEST_F(FoxgloveInterop, FoxgloveReadsTheLiveMeshMarkersAndCloud) {
  MeshBlock block;
  block.origin = {8, 0, -8};
  block.revision = 5;
  block.own_vertices = 3;
  // Vertices at 0, 1 and 2 voxels from the origin along x, y and z (4096 units a voxel).
  block.positions = {0, 0, 0, 0, 4096, 0, 0, 0, 8192};
  block.normals = {0, 0, 127, 0, 0, 127, 0, 0, 127};
  block.labels = {4, 4, 0};
  block.scores = {2.0F, 3.0F, 0.5F};
  block.colors = {10, 20, 30, 40, 50, 60, 70, 80, 90};
  block.triangles = {0, 1, 2};
  LabelLegend legend;
  legend.labels = {{4, "table", {230, 150, 30}}};
  wire::VisualizationStyle style;
  style.frame_id = "map";
  style.stamp = {3, 4};

  dds::Sample<visualization_msgs_msg_dds__MarkerArray_> markers;
  dds::resizeSequence(markers->markers, 1);
  wire::fillBlockMarker(markers->markers._buffer[0], block, 7, 0.1, legend, style);
  // Label 4 has its legend colour; the unlabeled vertex its own RGB.
  expectFoxgloveReads("visualization_msgs/MarkerArray", dds::serialize(*markers),
                      "markers.length=1\nmarkers[0].header.frame_id=\"map\"\nmarkers[0].header.stamp.sec=3\n"
                      "markers[0].ns=\"semfuse_map\"\nmarkers[0].id=7\nmarkers[0].type=11\nmarkers[0].action=0\n"
                      "markers[0].pose.orientation.w=1\nmarkers[0].scale.x=1\nmarkers[0].points.length=3\n"
                      "markers[0].points[0].x=0.8\nmarkers[0].points[0].z=-0.8\nmarkers[0].points[1].y=0.1\n"
                      "markers[0].points[2].z=-0.6000000000000001\nmarkers[0].colors.length=3\n"
                      "markers[0].colors[0].r=0.9019607901573181\nmarkers[0].colors[2].b=0.3529411852359772\n"
                      "markers[0].colors[2].a=1\n");

  dds::Sample<sensor_msgs_msg_dds__PointCloud2_> cloud;
  const std::vector<const MeshBlock*> blocks{&block};
  wire::fillSurfaceCloud(*cloud, blocks, 0.1, legend, style);
  // Point 0: label 4 at offset 16; point 2 (bytes 48-71): confidence 0.5 (0x3f000000) at 20.
  expectFoxgloveReads("sensor_msgs/PointCloud2", dds::serialize(*cloud),
                      "header.frame_id=\"map\"\nheight=1\nwidth=3\nfields.length=6\nfields[4].name=\"label\"\n"
                      "fields[4].offset=16\nfields[4].datatype=6\nfields[4].count=1\nfields[5].name=\"confidence\"\n"
                      "is_bigendian=false\npoint_step=24\nrow_step=72\ndata.length=72\nis_dense=true\n"
                      "data[16]=4\ndata[17]=0\ndata[64]=0\ndata[71]=63\n");
}

// foxglove's bytes written as they are (dds_writecdr) into a running server: a ROS camera
// (CameraInfo, tf, 16UC1 depth, rgb8 colour) and a native semfuse Frame are both integrated.
TEST_F(FoxgloveInterop, ServerIntegratesFramesFoxgloveSerialized) {
  ServerHarness h(interopDomain());
  h.startServer({"--legend", "synthetic", "--voxel-size", "0.02", "--truncation", "0.08", "--ros-ingest",
                 "--ros.camera-id", "fox-ros", "--ros.world-frame", "map", "--ros.wait", "2",
                 "--ros.compressed-color-topic", "/camera/color/image_raw/compressed"});
  const auto& p = h.participant();
  dds::Topic<sensor_msgs_msg_dds__CameraInfo_> info_topic(p, "rt/camera/depth/camera_info");
  dds::Topic<sensor_msgs_msg_dds__Image_> depth_topic(p, "rt/camera/depth/image_raw");
  dds::Topic<sensor_msgs_msg_dds__Image_> color_topic(p, "rt/camera/color/image_raw");
  dds::Topic<tf2_msgs_msg_dds__TFMessage_> tf_topic(p, "rt/tf");
  dds::Topic<semfuse_msg_dds__Frame_> frame_topic(p, dds::topics::kFrames);
  dds::RawWriter<sensor_msgs_msg_dds__CameraInfo_> info(info_topic, dds::qos::sensorData());
  dds::RawWriter<sensor_msgs_msg_dds__Image_> depth(depth_topic, dds::qos::sensorData());
  dds::RawWriter<sensor_msgs_msg_dds__Image_> color(color_topic, dds::qos::sensorData());
  dds::RawWriter<tf2_msgs_msg_dds__TFMessage_> tf(tf_topic, dds::Qos().reliable(DDS_SECS(2)).keepLast(100));
  dds::RawWriter<semfuse_msg_dds__Frame_> frames(frame_topic, dds::qos::frames());
  dds::Topic<sensor_msgs_msg_dds__CompressedImage_> compressed_topic(p, "rt/camera/color/image_raw/compressed");
  dds::RawWriter<sensor_msgs_msg_dds__CompressedImage_> compressed(compressed_topic, dds::qos::sensorData());
  ASSERT_TRUE(compressed.waitForReaders(1, DDS_SECS(30)));
  // What the server publishes on /tf (not this process's own writes).
  dds::Qos tf_reader_qos = dds::Qos().reliable(DDS_SECS(2)).keepLast(100);
  dds_qset_ignorelocal(tf_reader_qos.get(), DDS_IGNORELOCAL_PARTICIPANT);
  dds::Reader<tf2_msgs_msg_dds__TFMessage_> server_tf(tf_topic, tf_reader_qos);
  ASSERT_TRUE(info.waitForReaders(1, DDS_SECS(30)));
  ASSERT_TRUE(depth.waitForReaders(1, DDS_SECS(30)));
  ASSERT_TRUE(color.waitForReaders(1, DDS_SECS(30)));
  ASSERT_TRUE(tf.waitForReaders(1, DDS_SECS(30)));
  ASSERT_TRUE(frames.waitForReaders(1, DDS_SECS(30)));

  // A 64x48 camera 1.2 m in front of a wall, at the tf pose (90 degrees about z, 0.5/-1.25/1.5).
  std::string depth_flat =
      "header.stamp.sec=1700000000\nheader.stamp.nanosec=123456789\nheader.frame_id=\"camera_optical\"\n"
      "height=48\nwidth=64\nencoding=\"16UC1\"\nis_bigendian=0\nstep=128\ndata=[";
  std::string color_flat =
      "header.stamp.sec=1700000000\nheader.stamp.nanosec=123456789\nheader.frame_id=\"camera_optical\"\n"
      "height=48\nwidth=64\nencoding=\"rgb8\"\nis_bigendian=0\nstep=192\ndata=[";
  for (int i = 0; i < 64 * 48; ++i) {
    depth_flat += std::string(i ? "," : "") + "176,4";  // 1200 mm
    color_flat += std::string(i ? "," : "") + "200,100,50";
  }
  depth_flat += "]\n";
  color_flat += "]\n";
  ASSERT_TRUE(tf.write(foxgloveEncode("tf2_msgs/TFMessage", kTf)).ok());
  ASSERT_TRUE(info.write(foxgloveEncode("sensor_msgs/CameraInfo", kCameraInfo)).ok());
  ASSERT_TRUE(color.write(foxgloveEncode("sensor_msgs/Image", color_flat)).ok());
  ASSERT_TRUE(depth.write(foxgloveEncode("sensor_msgs/Image", depth_flat)).ok());

  auto ros_pose = h.waitPose("fox-ros", 1, 30s);
  ASSERT_TRUE(ros_pose) << "the ROS frame was not integrated";
  EXPECT_TRUE((*ros_pose)->posed);
  EXPECT_EQ((*ros_pose)->state, semfuse_msg_dds__TrackedPose_Constants_POSE_GIVEN);
  EXPECT_EQ((*ros_pose)->header.stamp.sec, 1700000000);
  EXPECT_EQ((*ros_pose)->header.stamp.nanosec, 123456789u);
  const Pose used = wire::poseFromRowMajor((*ros_pose)->camera_to_world);
  EXPECT_NEAR(used.translation().x(), 0.5, 1e-9);
  EXPECT_NEAR(used.translation().y(), -1.25, 1e-9);
  EXPECT_NEAR(used.linear()(1, 0), 1.0, 1e-9);

  // Frame 2, 100 ms later: 32FC1 depth (1.2 m) with a PNG-compressed colour image, and its tf.
  std::string tf2_flat = kTf;
  tf2_flat.replace(tf2_flat.find("nanosec=123456789"), 17, "nanosec=223456789");
  tf2_flat.replace(tf2_flat.find("translation.x=0.5"), 17, "translation.x=0.6");
  std::string depth32_flat =
      "header.stamp.sec=1700000000\nheader.stamp.nanosec=223456789\nheader.frame_id=\"camera_optical\"\n"
      "height=48\nwidth=64\nencoding=\"32FC1\"\nis_bigendian=0\nstep=256\ndata=[";
  for (int i = 0; i < 64 * 48; ++i) depth32_flat += std::string(i ? "," : "") + "154,153,153,63";  // 1.2f
  depth32_flat += "]\n";
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", cv::Mat(48, 64, CV_8UC3, cv::Scalar(50, 100, 200)), png));
  std::string png_flat =
      "header.stamp.sec=1700000000\nheader.stamp.nanosec=223456789\nheader.frame_id=\"camera_optical\"\n"
      "format=\"rgb8; png compressed bgr8\"\ndata=[";
  for (size_t i = 0; i < png.size(); ++i) png_flat += (i ? "," : "") + std::to_string(png[i]);
  png_flat += "]\n";
  ASSERT_TRUE(tf.write(foxgloveEncode("tf2_msgs/TFMessage", tf2_flat)).ok());
  ASSERT_TRUE(compressed.write(foxgloveEncode("sensor_msgs/CompressedImage", png_flat)).ok());
  ASSERT_TRUE(depth.write(foxgloveEncode("sensor_msgs/Image", depth32_flat)).ok());
  auto second = h.waitPose("fox-ros", 2, 30s);
  ASSERT_TRUE(second) << "the 32FC1 + PNG frame was not integrated";
  EXPECT_TRUE((*second)->posed);
  EXPECT_NEAR(wire::poseFromRowMajor((*second)->camera_to_world).translation().x(), 0.6, 1e-9);

  // Frame 3 has no colour: after --ros.wait it is dropped, and counted as ros_no_color.
  std::string lonely = depth32_flat;
  lonely.replace(lonely.find("nanosec=223456789"), 17, "nanosec=323456789");
  ASSERT_TRUE(depth.write(foxgloveEncode("sensor_msgs/Image", lonely)).ok());

  // A native frame from foxglove's bytes (a 2x1 frame is too small to integrate anything, but
  // it must be decoded, accepted and given its pose).
  std::string frame_flat = kFrame;
  frame_flat.replace(frame_flat.find("seq=18446744073709551615"), 24, "seq=0");
  ASSERT_TRUE(frames.write(foxgloveEncode("semfuse/Frame", frame_flat)).ok());
  auto native = h.waitPose("fox", 0, 30s);
  ASSERT_TRUE(native) << "the native frame was not processed";
  EXPECT_NEAR(wire::poseFromRowMajor((*native)->camera_to_world).translation().z(), 0.3, 1e-12);

  auto status = h.waitStatus([](const auto& s) { return counterTotal(s.dropped) >= 1; }, 20s);
  ASSERT_NE(status.get(), nullptr);
  EXPECT_EQ(status->frames_received, 4u);  // three ROS depth images and the native frame
  EXPECT_EQ(counterTotal(status->rejected), 0u);
  EXPECT_EQ(counterOf(status->dropped, "ros_no_color"), 1u);
  EXPECT_EQ(counterTotal(status->dropped), 1u);
  // --ros.publish-tf tracked (the default): poses that came from tf are not echoed on /tf.
  EXPECT_GE(server_tf.matchedWriters(), 1);
  EXPECT_FALSE(server_tf.take().has_value());
  EXPECT_GE(status->allocated_voxels, 1000u);  // the wall of the ROS frame
  EXPECT_EQ(h.stopServer(), 0);
}

}  // namespace
