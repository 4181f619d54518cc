// fastdds_peer: a ROS 2 style camera and listener built on Fast DDS with fastddsgen type
// support, to prove semfuse interoperates with a DDS implementation it did not write.
//
// It publishes the frames of a folder as a ROS 2 camera driver would (sensor_msgs Image depth
// 16UC1 + colour rgb8 + CameraInfo with sensor-data QoS, and tf2_msgs TFMessage world -> camera
// on /tf), and listens to what semfuse publishes for ROS 2 (/tf and /semfuse/status), printing
//   TF <sec> <nanosec> <parent> <child> <tx> <ty> <tz> <qx> <qy> <qz> <qw>
//   STATUS <frames_received> <frames_integrated> <dropped total> <rejected total>
// It exits 0 once every frame is published, `--expect-tf` transforms were received and a status
// reported at least `--expect-integrated` frames; 3 on timeout; 2 on bad usage or input.
//
// Folder layout (written by the test): camera.txt "width height fx fy cx cy", and per frame
// NNNN.depth (uint16 millimetres, little-endian, row-major), NNNN.rgb (uint8 RGB),
// NNNN.pose (12 numbers: row-major 3x4 camera-to-world). Frame i is stamped 1000 s + i * period.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "msgPubSubTypes.h"
#include "sensor_msgsPubSubTypes.h"
#include "tf2_msgsPubSubTypes.h"

using namespace eprosima::fastdds::dds;
namespace sm = sensor_msgs::msg::dds_;
namespace gm = geometry_msgs::msg::dds_;

namespace {

struct Options {
  int domain = 0;
  std::string frames_dir;
  double rate_hz = 10.0;
  std::string world_frame = "map";
  std::string camera_frame = "camera_optical";
  bool publish_tf = true;
  int expect_tf = 0;
  int expect_integrated = 0;
  double timeout_s = 60.0;
};

void usage(std::ostream& out) {
  out << "usage: fastdds_peer --domain N [--frames DIR] [--rate HZ] [--world-frame F] [--camera-frame F]\n"
         "                    [--no-tf] [--expect-tf N] [--expect-integrated N] [--timeout S]\n"
         "Publishes a frame folder as ROS 2 topics with Fast DDS and listens to semfuse's /tf and status.\n";
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      usage(std::cout);
      std::exit(0);
    } else if (a == "--domain") o.domain = std::stoi(value());
    else if (a == "--frames") o.frames_dir = value();
    else if (a == "--rate") o.rate_hz = std::stod(value());
    else if (a == "--world-frame") o.world_frame = value();
    else if (a == "--camera-frame") o.camera_frame = value();
    else if (a == "--no-tf") o.publish_tf = false;
    else if (a == "--expect-tf") o.expect_tf = std::stoi(value());
    else if (a == "--expect-integrated") o.expect_integrated = std::stoi(value());
    else if (a == "--timeout") o.timeout_s = std::stod(value());
    else throw std::invalid_argument("unknown option " + a);
  }
  return o.rate_hz > 0;
}

std::vector<uint8_t> readBytes(const std::string& path, size_t expected) {
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw std::runtime_error("cannot read " + path);
  if (bytes.size() != expected)
    throw std::runtime_error(path + ": " + std::to_string(bytes.size()) + " bytes, expected " +
                             std::to_string(expected));
  return bytes;
}

struct Camera {
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

// The participant talks UDP on 127.0.0.1 only: Fast DDS's default shared-memory transport is
// invisible to Cyclone, and a participant id above Cyclone's auto indices keeps ports apart.
// Discovery is unicast to the ports of participant indices 0..19 on localhost, as Cyclone's
// loopback profile (no multicast) expects.
DomainParticipant* makeParticipant(int domain) {
  DomainParticipantQos qos;
  qos.name("fastdds_peer");
  qos.transport().use_builtin_transports = false;
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back("127.0.0.1");
  udp->maxMessageSize = 65000;
  qos.transport().user_transports.push_back(udp);
  qos.wire_protocol().participant_id = 40;
  for (int index = 0; index < 20; ++index) {
    eprosima::fastrtps::rtps::Locator_t peer;
    eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, 127, 0, 0, 1);
    peer.port = static_cast<uint32_t>(7400 + 250 * domain + 10 + 2 * index);
    qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  }
  return DomainParticipantFactory::get_instance()->create_participant(domain, qos);
}

void setStamp(std_msgs::msg::dds_::Header_& header, int index, double rate_hz, const std::string& frame_id) {
  const double t = 1000.0 + index / rate_hz;
  header.stamp().sec(static_cast<int32_t>(std::floor(t)));
  header.stamp().nanosec(static_cast<uint32_t>(std::llround((t - std::floor(t)) * 1e9)));
  header.frame_id(frame_id);
}

// Row-major rotation -> quaternion (the rotation is orthonormal: it comes from the renderer).
std::array<double, 4> quaternion(const std::array<double, 12>& m) {
  const double r00 = m[0], r01 = m[1], r02 = m[2], r10 = m[4], r11 = m[5], r12 = m[6], r20 = m[8], r21 = m[9],
               r22 = m[10];
  const double trace = r00 + r11 + r22;
  double x, y, z, w;
  if (trace > 0) {
    const double s = 0.5 / std::sqrt(trace + 1.0);
    w = 0.25 / s;
    x = (r21 - r12) * s;
    y = (r02 - r20) * s;
    z = (r10 - r01) * s;
  } else if (r00 > r11 && r00 > r22) {
    const double s = 2.0 * std::sqrt(1.0 + r00 - r11 - r22);
    w = (r21 - r12) / s;
    x = 0.25 * s;
    y = (r01 + r10) / s;
    z = (r02 + r20) / s;
  } else if (r11 > r22) {
    const double s = 2.0 * std::sqrt(1.0 + r11 - r00 - r22);
    w = (r02 - r20) / s;
    x = (r01 + r10) / s;
    y = 0.25 * s;
    z = (r12 + r21) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r22 - r00 - r11);
    w = (r10 - r01) / s;
    x = (r02 + r20) / s;
    y = (r12 + r21) / s;
    z = 0.25 * s;
  }
  return {x, y, z, w};
}

class Peer {
 public:
  explicit Peer(const Options& o) : o_(o) {
    participant_ = makeParticipant(o.domain);
    if (!participant_) throw std::runtime_error("create_participant failed");
    for (TypeSupport t : {TypeSupport(new sm::Image_PubSubType()), TypeSupport(new sm::CameraInfo_PubSubType()),
                          TypeSupport(new tf2_msgs::msg::dds_::TFMessage_PubSubType()),
                          TypeSupport(new semfuse::msg::dds_::ServerStatus_PubSubType())}) {
      t.register_type(participant_);
    }
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);

    // rclcpp's SensorDataQoS: best effort, keep last 5, volatile.
    DataWriterQos sensor = DATAWRITER_QOS_DEFAULT;
    sensor.reliability().kind = BEST_EFFORT_RELIABILITY_QOS;
    sensor.durability().kind = VOLATILE_DURABILITY_QOS;
    sensor.history().kind = KEEP_LAST_HISTORY_QOS;
    sensor.history().depth = 5;
    // rclcpp's tf broadcaster: reliable, keep last 100.
    DataWriterQos tf = DATAWRITER_QOS_DEFAULT;
    tf.reliability().kind = RELIABLE_RELIABILITY_QOS;
    tf.durability().kind = VOLATILE_DURABILITY_QOS;
    tf.history().kind = KEEP_LAST_HISTORY_QOS;
    tf.history().depth = 100;

    depth_ = writer("rt/camera/depth/image_raw", "sensor_msgs::msg::dds_::Image_", sensor);
    color_ = writer("rt/camera/color/image_raw", "sensor_msgs::msg::dds_::Image_", sensor);
    info_ = writer("rt/camera/depth/camera_info", "sensor_msgs::msg::dds_::CameraInfo_", sensor);
    tf_ = writer("rt/tf", "tf2_msgs::msg::dds_::TFMessage_", tf);

    DataReaderQos tf_in = DATAREADER_QOS_DEFAULT;
    tf_in.reliability().kind = RELIABLE_RELIABILITY_QOS;
    tf_in.history().kind = KEEP_LAST_HISTORY_QOS;
    tf_in.history().depth = 100;
    DataReaderQos status_in = DATAREADER_QOS_DEFAULT;  // semfuse's status: reliable, transient-local
    status_in.reliability().kind = RELIABLE_RELIABILITY_QOS;
    status_in.durability().kind = TRANSIENT_LOCAL_DURABILITY_QOS;
    status_in.history().kind = KEEP_LAST_HISTORY_QOS;
    status_in.history().depth = 1;
    tf_reader_ = reader(tf_topic_, tf_in);
    status_reader_ = reader(topic("rt/semfuse/status", "semfuse::msg::dds_::ServerStatus_"), status_in);
  }

  ~Peer() {
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }

  int run() {
    const auto deadline =
        std::chrono::steady_clock::now() +
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(o_.timeout_s));
    std::vector<std::string> frames;
    Camera camera;
    if (!o_.frames_dir.empty()) {
      std::ifstream in(o_.frames_dir + "/camera.txt");
      if (!(in >> camera.width >> camera.height >> camera.fx >> camera.fy >> camera.cx >> camera.cy))
        throw std::runtime_error(o_.frames_dir + "/camera.txt: expected 'width height fx fy cx cy'");
      for (int i = 0;; ++i) {
        char name[16];
        std::snprintf(name, sizeof name, "%04d", i);
        if (!std::ifstream(o_.frames_dir + "/" + name + ".depth")) break;
        frames.push_back(o_.frames_dir + "/" + name);
      }
      if (frames.empty()) throw std::runtime_error(o_.frames_dir + ": no frames");
      // Best-effort samples sent before the server's readers match are lost: wait for them.
      waitMatched(depth_, deadline);
      waitMatched(color_, deadline);
      waitMatched(info_, deadline);
      if (o_.publish_tf) waitMatched(tf_, deadline);
    }
    const auto period = std::chrono::duration<double>(1.0 / o_.rate_hz);
    auto next = std::chrono::steady_clock::now();
    for (size_t i = 0; i < frames.size(); ++i) {
      publishFrame(static_cast<int>(i), frames[i], camera);
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      std::this_thread::sleep_until(next);
      drainReaders();
    }
    std::cerr << "fastdds_peer: published " << frames.size() << " frames\n";
    while (std::chrono::steady_clock::now() < deadline) {
      drainReaders();
      if (tf_received_ >= o_.expect_tf && integrated_ >= o_.expect_integrated && status_seen_) return 0;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::cerr << "fastdds_peer: timeout: " << tf_received_ << "/" << o_.expect_tf << " tf, " << integrated_ << "/"
              << o_.expect_integrated << " frames integrated in status\n";
    return 3;
  }

 private:
  Topic* topic(const std::string& name, const std::string& type) {
    Topic* t = participant_->create_topic(name, type, TOPIC_QOS_DEFAULT);
    if (!t) throw std::runtime_error("create_topic " + name);
    if (name == "rt/tf") tf_topic_ = t;
    return t;
  }
  DataWriter* writer(const std::string& name, const std::string& type, const DataWriterQos& qos) {
    DataWriter* w = publisher_->create_datawriter(topic(name, type), qos);
    if (!w) throw std::runtime_error("create_datawriter " + name);
    return w;
  }
  DataReader* reader(Topic* t, const DataReaderQos& qos) {
    DataReader* r = subscriber_->create_datareader(t, qos);
    if (!r) throw std::runtime_error("create_datareader " + t->get_name());
    return r;
  }
  static void waitMatched(DataWriter* w, std::chrono::steady_clock::time_point deadline) {
    PublicationMatchedStatus status;
    while (std::chrono::steady_clock::now() < deadline) {
      w->get_publication_matched_status(status);
      if (status.current_count > 0) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    throw std::runtime_error("no reader matched " + w->get_topic()->get_name());
  }

  void publishFrame(int index, const std::string& stem, const Camera& c) {
    const size_t pixels = static_cast<size_t>(c.width) * c.height;
    std::array<double, 12> pose{};
    {
      std::ifstream in(stem + ".pose");
      for (double& v : pose)
        if (!(in >> v)) throw std::runtime_error(stem + ".pose: expected 12 numbers");
    }
    if (o_.publish_tf) {  // the transform first, as a driver's tf usually leads its images
      tf2_msgs::msg::dds_::TFMessage_ msg;
      gm::TransformStamped_ t;
      setStamp(t.header(), index, o_.rate_hz, o_.world_frame);
      t.child_frame_id(o_.camera_frame);
      t.transform().translation().x(pose[3]);
      t.transform().translation().y(pose[7]);
      t.transform().translation().z(pose[11]);
      const auto q = quaternion(pose);
      t.transform().rotation().x(q[0]);
      t.transform().rotation().y(q[1]);
      t.transform().rotation().z(q[2]);
      t.transform().rotation().w(q[3]);
      msg.transforms().push_back(t);
      tf_->write(&msg);
    }
    sm::CameraInfo_ info;
    setStamp(info.header(), index, o_.rate_hz, o_.camera_frame);
    info.width(c.width);
    info.height(c.height);
    info.distortion_model("plumb_bob");
    info.d(std::vector<double>(5, 0.0));
    info.k({c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1});
    info.r({1, 0, 0, 0, 1, 0, 0, 0, 1});
    info.p({c.fx, 0, c.cx, 0, 0, c.fy, c.cy, 0, 0, 0, 1, 0});
    info_->write(&info);

    sm::Image_ color;
    setStamp(color.header(), index, o_.rate_hz, o_.camera_frame);
    color.width(c.width);
    color.height(c.height);
    color.encoding("rgb8");
    color.step(c.width * 3);
    color.data(readBytes(stem + ".rgb", pixels * 3));
    color_->write(&color);

    sm::Image_ depth;
    setStamp(depth.header(), index, o_.rate_hz, o_.camera_frame);
    depth.width(c.width);
    depth.height(c.height);
    depth.encoding("16UC1");
    depth.step(c.width * 2);
    depth.data(readBytes(stem + ".depth", pixels * 2));
    depth_->write(&depth);
  }

  void drainReaders() {
    tf2_msgs::msg::dds_::TFMessage_ tf;
    SampleInfo info;
    while (tf_reader_->take_next_sample(&tf, &info) == ReturnCode_t::RETCODE_OK) {
      // The reader also hears this peer's own /tf writer: only the server's transforms count.
      if (!info.valid_data || info.publication_handle == tf_->get_instance_handle()) continue;
      for (const auto& t : tf.transforms()) {
        ++tf_received_;
        const auto& p = t.transform().translation();
        const auto& q = t.transform().rotation();
        std::printf("TF %d %u %s %s %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t.header().stamp().sec(),
                    t.header().stamp().nanosec(), t.header().frame_id().c_str(), t.child_frame_id().c_str(), p.x(),
                    p.y(), p.z(), q.x(), q.y(), q.z(), q.w());
      }
    }
    semfuse::msg::dds_::ServerStatus_ status;
    while (status_reader_->take_next_sample(&status, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      status_seen_ = true;
      integrated_ = static_cast<int>(status.frames_integrated());
      uint64_t dropped = 0, rejected = 0;
      for (const auto& c : status.dropped()) dropped += c.count();
      for (const auto& c : status.rejected()) rejected += c.count();
      std::printf("STATUS %llu %llu %llu %llu %s\n", static_cast<unsigned long long>(status.frames_received()),
                  static_cast<unsigned long long>(status.frames_integrated()), static_cast<unsigned long long>(dropped),
                  static_cast<unsigned long long>(rejected), status.server_id().c_str());
    }
    std::fflush(stdout);
  }

  Options o_;
  DomainParticipant* participant_ = nullptr;
  Publisher* publisher_ = nullptr;
  Subscriber* subscriber_ = nullptr;
  Topic* tf_topic_ = nullptr;
  DataWriter *depth_ = nullptr, *color_ = nullptr, *info_ = nullptr, *tf_ = nullptr;
  DataReader *tf_reader_ = nullptr, *status_reader_ = nullptr;
  int tf_received_ = 0;
  int integrated_ = 0;
  bool status_seen_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    if (!parse(argc, argv, options)) throw std::invalid_argument("--rate must be > 0");
  } catch (const std::exception& e) {
    std::cerr << "fastdds_peer: " << e.what() << "\n";
    usage(std::cerr);
    return 2;
  }
  try {
    Peer peer(options);
    return peer.run();
  } catch (const std::exception& e) {
    std::cerr << "fastdds_peer: " << e.what() << "\n";
    return 2;
  }
}
