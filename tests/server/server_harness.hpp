#pragma once
// A real semfuse-server process on loopback DDS, and the DDS endpoints a test needs to feed it
// and to watch it: frames and segmentations writers, a poses reader, a status reader and the
// admin and raycast service clients.
#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "child_process.hpp"
#include "msg.h"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/writer.hpp"
#include "srv.h"
#include "test_domain.hpp"

namespace semfuse::testing {

// A domain of this test process's own (test_domain.hpp).
inline dds_domainid_t serverTestDomain() { return static_cast<dds_domainid_t>(reserveTestDomain()); }

inline std::string loopbackProfile() { return std::string(SEMFUSE_SOURCE_DIR) + "/deploy/dds/localhost.xml"; }

// Count of a reason in a status counter sequence, summed over cameras.
inline uint64_t counterOf(const dds_sequence_semfuse_msg_dds__Counter_& counters, const std::string& reason) {
  uint64_t sum = 0;
  for (uint32_t i = 0; i < counters._length; ++i)
    if (reason == counters._buffer[i].reason) sum += counters._buffer[i].count;
  return sum;
}
inline uint64_t counterTotal(const dds_sequence_semfuse_msg_dds__Counter_& counters) {
  uint64_t sum = 0;
  for (uint32_t i = 0; i < counters._length; ++i) sum += counters._buffer[i].count;
  return sum;
}

class ServerHarness {
 public:
  explicit ServerHarness(dds_domainid_t domain)
      : domain_(domain),
        participant_((setProfile(), domain)),
        frame_topic_(participant_, dds::topics::kFrames),
        segmentation_topic_(participant_, dds::topics::kSegmentations),
        pose_topic_(participant_, dds::topics::kPoses),
        status_topic_(participant_, dds::topics::kStatus),
        frames_(frame_topic_, dds::qos::frames()),
        segmentations_(segmentation_topic_, dds::qos::segmentations()),
        poses_(pose_topic_, dds::qos::poses()),
        status_(status_topic_, dds::qos::status()),
        admin_(participant_, dds::topics::admin()),
        raycast_(participant_, dds::topics::raycast()) {}

  // Starts semfuse-server with the loopback profile, this harness's domain and `args`; waits
  // until it reads frames.
  void startServer(const std::vector<std::string>& args) {
    std::vector<std::string> argv{
        SEMFUSE_SERVER_EXE, "--domain-id", std::to_string(domain_), "--dds-profile", loopbackProfile(),
        "--log-level",      "warn"};
    argv.insert(argv.end(), args.begin(), args.end());
    server_ = std::make_unique<ChildProcess>(argv);
    ASSERT_TRUE(frames_.waitForReaders(1, DDS_SECS(30))) << "semfuse-server did not come up";
    ASSERT_TRUE(segmentations_.waitForReaders(1, DDS_SECS(30)));
  }

  // SIGTERM and wait; returns the exit code.
  int stopServer() {
    const int code = server_ ? server_->stop() : -1;
    server_.reset();
    return code;
  }
  bool serverRunning() { return server_ && server_->running(); }

  // Waits for the pose the server publishes for (camera, seq).
  std::optional<dds::Sample<semfuse_msg_dds__TrackedPose_>> waitPose(const std::string& camera, uint64_t seq,
                                                                     std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      while (auto pose = poses_.take())
        if ((*pose)->seq == seq && camera == (*pose)->camera_id) return std::move(*pose);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return std::nullopt;
  }

  // Latest status satisfying `done`, or the last one seen when the timeout passes.
  dds::Sample<semfuse_msg_dds__ServerStatus_> waitStatus(
      const std::function<bool(const semfuse_msg_dds__ServerStatus_&)>& done, std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      while (auto status = status_.take()) latest_ = std::move(*status);
      if (latest_ && done(**latest_)) break;
      if (std::chrono::steady_clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    dds::Sample<semfuse_msg_dds__ServerStatus_> copy;
    if (latest_) {
      auto bytes = dds::serialize(**latest_);
      if (auto back = dds::deserialize<semfuse_msg_dds__ServerStatus_>(bytes.data(), bytes.size()); back.ok())
        copy = std::move(back).value();
    }
    return copy;
  }

  dds::Writer<semfuse_msg_dds__Frame_>& frames() { return frames_; }
  dds::Writer<semfuse_msg_dds__Segmentation_>& segmentations() { return segmentations_; }
  dds::RpcClient<semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_>& admin() { return admin_; }
  // Saves the map through the admin service into the server's --map file; fails the test otherwise.
  void saveMap() {
    semfuse_srv_dds__Admin_Request_ save{};
    save.command = semfuse_srv_dds__Admin_Request_Constants_SAVE;
    save.path = const_cast<char*>("");
    auto saved = admin_.call(save, std::chrono::seconds(30));
    ASSERT_TRUE(saved.ok()) << saved.error();
    ASSERT_EQ(saved.value()->status, 0) << dds::replyMessage(*saved.value());
  }
  dds::RpcClient<semfuse_srv_dds__Raycast_Request_, semfuse_srv_dds__Raycast_Response_>& raycast() { return raycast_; }
  const dds::Participant& participant() const { return participant_; }

 private:
  static void setProfile() { ::setenv("CYCLONEDDS_URI", ("file://" + loopbackProfile()).c_str(), 1); }

  dds_domainid_t domain_;
  dds::Participant participant_;
  dds::Topic<semfuse_msg_dds__Frame_> frame_topic_;
  dds::Topic<semfuse_msg_dds__Segmentation_> segmentation_topic_;
  dds::Topic<semfuse_msg_dds__TrackedPose_> pose_topic_;
  dds::Topic<semfuse_msg_dds__ServerStatus_> status_topic_;
  dds::Writer<semfuse_msg_dds__Frame_> frames_;
  dds::Writer<semfuse_msg_dds__Segmentation_> segmentations_;
  dds::Reader<semfuse_msg_dds__TrackedPose_> poses_;
  dds::Reader<semfuse_msg_dds__ServerStatus_> status_;
  dds::RpcClient<semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_> admin_;
  dds::RpcClient<semfuse_srv_dds__Raycast_Request_, semfuse_srv_dds__Raycast_Response_> raycast_;
  std::optional<dds::Sample<semfuse_msg_dds__ServerStatus_>> latest_;
  std::unique_ptr<ChildProcess> server_;
};

}  // namespace semfuse::testing
