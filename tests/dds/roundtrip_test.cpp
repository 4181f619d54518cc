// Every wire type through Cyclone between two real processes on loopback: this process writes
// a sample with distinct known values, semfuse_dds_echo decodes and republishes it, and the
// echoed sample must serialize to exactly the bytes that were sent.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include <memory>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "dds_test_env.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/raw.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "wire_fill.hpp"
#include "wire_types.hpp"

namespace semfuse::dds {
namespace {

constexpr dds_duration_t kEchoTimeout = DDS_SECS(20);

// One typed path to the echo process and back.
template <class T>
class Loop {
 public:
  Loop(const Participant& participant, const std::string& prefix, const Qos& qos)
      : out_topic_(participant, prefix + "/in/" + testing::topicSuffix<T>()),
        back_topic_(participant, prefix + "/out/" + testing::topicSuffix<T>()),
        writer_(out_topic_, qos),
        reader_(back_topic_, qos),
        data_(reader_.handle()),
        waitset_(participant) {
    waitset_.attach(data_.handle());
  }

  bool connected() const {
    return writer_.waitForReaders(1, testing::kDiscoveryTimeout) &&
           reader_.waitForWriters(1, testing::kDiscoveryTimeout);
  }

  // Sends the sample and returns the serialized bytes of what came back (empty on timeout).
  std::vector<uint8_t> echo(const T& sample) {
    if (!writer_.write(sample)) return {};
    const dds_time_t deadline = dds_time() + kEchoTimeout;
    while (dds_time() < deadline) {
      auto received = takeSerialized(reader_.handle(), 1);
      if (received.ok() && !received.value().empty()) return received.value().front();
      if (!waitset_.wait(deadline - dds_time())) break;
    }
    return {};
  }

 private:
  Topic<T> out_topic_;
  Topic<T> back_topic_;
  Writer<T> writer_;
  Reader<T> reader_;
  ReadCondition data_;
  WaitSet waitset_;
};

class RoundTrip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { testing::useLoopbackConfig(); }
  void SetUp() override {
    echo_ = std::make_unique<semfuse::testing::ChildProcess>(
        std::vector<std::string>{SEMFUSE_DDS_ECHO, std::to_string(domain_), prefix_});
  }
  void TearDown() override { echo_.reset(); }

  template <class T>
  void expectEchoed(Loop<T>& loop, const T& sample, const char* what) {
    const std::vector<uint8_t> sent = serialize(sample);
    const std::vector<uint8_t> back = loop.echo(sample);
    ASSERT_FALSE(back.empty()) << what << ": no echo within the timeout";
    EXPECT_EQ(back.size(), sent.size()) << what;
    EXPECT_TRUE(back == sent) << what << ": echoed bytes differ";
    auto decoded = deserialize<T>(back);
    ASSERT_TRUE(decoded.ok()) << what << ": " << decoded.error();
  }

  // Transient-local on both sides: a writer may see the echo's reader before that reader
  // knows the writer; history makes a sample written in that window arrive anyway.
  const dds_domainid_t domain_ = testing::testDomain();
  const std::string prefix_ = testing::uniqueName("roundtrip");
  const Qos qos_ = Qos().reliable(qos::kMaxBlockingTime).keepAll().transientLocal();
  Participant participant_{domain_};
  std::unique_ptr<semfuse::testing::ChildProcess> echo_;
};

TEST_F(RoundTrip, EveryWireTypeComesBackUnchanged) {
  int checked = 0;
  testing::forEachWireType([&](auto tag) {
    using T = typename decltype(tag)::type;
    Loop<T> loop(participant_, prefix_, qos_);
    ASSERT_TRUE(loop.connected()) << descriptorOf<T>().m_typename << ": echo process not discovered";
    const auto sample = testing::filledSample<T>(static_cast<uint32_t>(100 + checked));
    expectEchoed(loop, *sample, descriptorOf<T>().m_typename);
    ++checked;
  });
  EXPECT_EQ(checked, testing::kWireTypeCount);
}

// A 640x480 RGB-D frame: 16-bit depth and rgb8 colour, raw, then PNG depth + JPEG colour.
class Frame640 {
 public:
  Frame640() : depth_(480, 640, CV_16UC1), color_(480, 640, CV_8UC3) {
    for (int v = 0; v < depth_.rows; ++v) {
      for (int u = 0; u < depth_.cols; ++u) {
        depth_.at<uint16_t>(v, u) = static_cast<uint16_t>(500 + 3 * u + 7 * v);
        color_.at<cv::Vec3b>(v, u) =
            cv::Vec3b(static_cast<uint8_t>(u), static_cast<uint8_t>(v), static_cast<uint8_t>(u ^ v));
      }
    }
  }

  Sample<semfuse_msg_dds__Frame_> raw() const {
    auto frame = base();
    setString(frame->depth_encoding, "16UC1");
    setSequence(frame->depth, depth_.data, depth_.total() * depth_.elemSize());
    setString(frame->color_encoding, "rgb8");
    setSequence(frame->color, color_.data, color_.total() * color_.elemSize());
    return frame;
  }

  Sample<semfuse_msg_dds__Frame_> encoded() const {
    auto frame = base();
    std::vector<uint8_t> png, jpeg;
    cv::imencode(".png", depth_, png);
    cv::imencode(".jpg", color_, jpeg);
    setString(frame->depth_encoding, "png16");
    setSequence(frame->depth, png.data(), png.size());
    setString(frame->color_encoding, "jpeg");
    setSequence(frame->color, jpeg.data(), jpeg.size());
    return frame;
  }

 private:
  Sample<semfuse_msg_dds__Frame_> base() const {
    Sample<semfuse_msg_dds__Frame_> frame;
    frame->header.stamp = {1700000000, 123456789};
    setString(frame->header.frame_id, "kinect_rgb_optical");
    setString(frame->camera_id, "kitchen");
    frame->seq = 42;
    frame->intrinsics = {640, 480, 585.0, 586.0, 320.5, 240.5};
    frame->depth_scale = 0.001f;
    frame->has_pose = true;
    const double pose[12] = {1, 0, 0, 0.5, 0, 1, 0, -0.25, 0, 0, 1, 1.5};
    std::copy(pose, pose + 12, frame->camera_to_world);
    return frame;
  }

  cv::Mat depth_;
  cv::Mat color_;
};

TEST_F(RoundTrip, Frame640x480RawAndEncodedComeBackUnchanged) {
  Loop<semfuse_msg_dds__Frame_> loop(participant_, prefix_, qos_);
  ASSERT_TRUE(loop.connected()) << "echo process not discovered";
  const Frame640 source;
  const auto raw = source.raw();
  ASSERT_EQ(raw->depth._length, 640u * 480u * 2u);
  ASSERT_EQ(raw->color._length, 640u * 480u * 3u);
  expectEchoed(loop, *raw, "raw 640x480 frame");

  const auto encoded = source.encoded();
  ASSERT_GT(encoded->depth._length, 1000u);
  ASSERT_GT(encoded->color._length, 1000u);
  expectEchoed(loop, *encoded, "PNG/JPEG 640x480 frame");
  EXPECT_TRUE(echo_->running());
}

}  // namespace
}  // namespace semfuse::dds
