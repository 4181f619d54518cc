// The RAII wrappers in one process: errors carry Cyclone's text, loaned and copying takes see
// what was written, raw bytes go out unchanged, and the QoS profiles say what docs/architecture.md says.
#include <gtest/gtest.h>

#include <string>

#include "dds_test_env.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/raw.hpp"
#include "semfuse/dds/reader.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/waitset.hpp"
#include "semfuse/dds/writer.hpp"
#include "wire_fill.hpp"

namespace semfuse::dds {
namespace {

using Pose = semfuse_msg_dds__TrackedPose_;

class Wrappers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { testing::useLoopbackConfig(); }
  Participant participant{testing::testDomain()};
  const Qos qos = Qos().reliable(DDS_SECS(1)).keepAll();
};

TEST_F(Wrappers, ConstructionErrorsCarryCycloneText) {
  try {
    Topic<Pose> bad(participant, "");  // an empty topic name is invalid
    FAIL() << "expected DdsError";
  } catch (const DdsError& e) {
    EXPECT_NE(std::string(e.what()).find("create topic : Bad Parameter"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), DDS_RETCODE_BAD_PARAMETER);
  }
}

TEST_F(Wrappers, LoanedAndCopyingTakeSeeTheWrittenSamples) {
  Topic<Pose> topic(participant, testing::uniqueName("poses"));
  Writer<Pose> writer(topic, qos);
  Reader<Pose> reader(topic, qos);
  auto first = testing::filledSample<Pose>(1);
  auto second = testing::filledSample<Pose>(2);
  ASSERT_TRUE(writer.write(*first));
  ASSERT_TRUE(writer.write(*second));

  // Delivery inside one process is synchronous: no waiting needed.
  std::vector<uint64_t> seqs;
  auto taken = reader.takeLoaned(1, [&](const Pose& p, const dds_sample_info_t& info) {
    EXPECT_TRUE(info.valid_data);
    seqs.push_back(p.seq);
  });
  ASSERT_TRUE(taken.ok()) << taken.error();
  EXPECT_EQ(taken.value(), 1u);
  auto copy = reader.take();
  ASSERT_TRUE(copy.has_value());
  seqs.push_back((*copy)->seq);
  EXPECT_EQ(seqs, (std::vector<uint64_t>{first->seq, second->seq}));
  EXPECT_STREQ((*copy)->camera_id, second->camera_id);
  EXPECT_FALSE(reader.take().has_value());
}

TEST_F(Wrappers, ReadConditionWakesAWaitSetAndGuardConditionToo) {
  Topic<Pose> topic(participant, testing::uniqueName("poses"));
  Writer<Pose> writer(topic, qos);
  Reader<Pose> reader(topic, qos);
  ReadCondition data(reader.handle());
  GuardCondition guard(participant);
  WaitSet waitset(participant);
  waitset.attach(data.handle());
  waitset.attach(guard.handle());

  auto idle = waitset.wait(0);
  ASSERT_TRUE(idle.ok());
  EXPECT_TRUE(idle.value().empty());

  ASSERT_TRUE(writer.write(*testing::filledSample<Pose>(3)));
  auto woke = waitset.wait(DDS_SECS(5));
  ASSERT_TRUE(woke.ok());
  EXPECT_EQ(woke.value(), std::vector<dds_entity_t>{data.handle()});
  EXPECT_EQ(reader.takeAll().size(), 1u);

  guard.trigger();
  woke = waitset.wait(DDS_SECS(5));
  ASSERT_TRUE(woke.ok());
  EXPECT_EQ(woke.value(), std::vector<dds_entity_t>{guard.handle()});
  EXPECT_TRUE(guard.triggered());
}

TEST_F(Wrappers, SerializeGivesTheBytesCycloneWrites) {
  Topic<semfuse_msg_dds__ServerStatus_> topic(participant, testing::uniqueName("status"));
  Writer<semfuse_msg_dds__ServerStatus_> writer(topic, qos);
  Reader<semfuse_msg_dds__ServerStatus_> reader(topic, qos);
  auto status = testing::filledSample<semfuse_msg_dds__ServerStatus_>(4);
  ASSERT_TRUE(writer.write(*status));
  auto raw = takeSerialized(reader.handle());
  ASSERT_TRUE(raw.ok()) << raw.error();
  ASSERT_EQ(raw.value().size(), 1u);
  EXPECT_EQ(raw.value()[0], serialize(*status));
}

TEST_F(Wrappers, RawWriterSendsForeignBytesAndRefusesMalformedOnes) {
  using Image = sensor_msgs_msg_dds__Image_;
  Topic<Image> topic(participant, testing::uniqueName("image"));
  RawWriter<Image> writer(topic, qos);
  Reader<Image> reader(topic, qos);
  auto image = testing::filledSample<Image>(5);
  std::vector<uint8_t> bytes = serialize(*image);
  ASSERT_TRUE(writer.write(bytes));
  auto got = reader.take();
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(serialize(**got), bytes);
  EXPECT_STREQ((*got)->header.frame_id, image->header.frame_id);

  bytes.resize(bytes.size() - 8);
  Status bad = writer.write(bytes);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().find("malformed CDR for sensor_msgs::msg::dds_::Image_"), std::string::npos) << bad.error();
  EXPECT_FALSE(reader.take().has_value());
}

TEST(Qos, ProfilesMatchTheDesign) {
  struct Expect {
    Qos qos;
    dds_reliability_kind_t reliability;
    int depth;
    dds_durability_kind_t durability;
  };
  const Expect expectations[] = {
      {qos::frames(), DDS_RELIABILITY_RELIABLE, 2, DDS_DURABILITY_VOLATILE},
      {qos::segmentations(), DDS_RELIABILITY_RELIABLE, 8, DDS_DURABILITY_VOLATILE},
      {qos::poses(), DDS_RELIABILITY_RELIABLE, 10, DDS_DURABILITY_VOLATILE},
      {qos::status(), DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL},
      {qos::legend(), DDS_RELIABILITY_RELIABLE, 1, DDS_DURABILITY_TRANSIENT_LOCAL},
      {qos::service(), DDS_RELIABILITY_RELIABLE, 10, DDS_DURABILITY_VOLATILE},
      {qos::sensorData(), DDS_RELIABILITY_BEST_EFFORT, 5, DDS_DURABILITY_VOLATILE},
  };
  for (const auto& e : expectations) {
    dds_reliability_kind_t reliability{};
    dds_duration_t blocking = 0;
    ASSERT_TRUE(dds_qget_reliability(e.qos.get(), &reliability, &blocking));
    EXPECT_EQ(reliability, e.reliability);
    if (reliability == DDS_RELIABILITY_RELIABLE) {
      EXPECT_EQ(blocking, qos::kMaxBlockingTime);
    }
    dds_history_kind_t history{};
    int32_t depth = 0;
    ASSERT_TRUE(dds_qget_history(e.qos.get(), &history, &depth));
    EXPECT_EQ(history, DDS_HISTORY_KEEP_LAST);
    EXPECT_EQ(depth, e.depth);
    dds_durability_kind_t durability{};
    ASSERT_TRUE(dds_qget_durability(e.qos.get(), &durability));
    EXPECT_EQ(durability, e.durability);
  }
}

TEST(Topics, NamesFollowRos2Conventions) {
  EXPECT_STREQ(topics::kFrames, "rt/semfuse/frames");
  EXPECT_STREQ(topics::kLabels, "rt/semfuse/labels");
  EXPECT_EQ(topics::labelsAt().request, "rq/semfuse/labels_atRequest");
  EXPECT_EQ(topics::labelsAt().reply, "rr/semfuse/labels_atReply");
  EXPECT_EQ(topics::admin().request, "rq/semfuse/adminRequest");
  EXPECT_EQ(topics::service("add_two_ints", "").reply, "rr/add_two_intsReply");
}

TEST(SampleOwnership, MoveTransfersTheSample) {
  auto a = testing::filledSample<semfuse_msg_dds__Counter_>(9);
  const char* reason = a->reason;
  Sample<semfuse_msg_dds__Counter_> b = std::move(a);
  EXPECT_EQ(b->reason, reason);
  EXPECT_EQ(a.get(), nullptr);  // NOLINT(bugprone-use-after-move): checking the moved-from state
}

}  // namespace
}  // namespace semfuse::dds
