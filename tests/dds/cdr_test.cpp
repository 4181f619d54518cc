// serialize()/deserialize(): exact bytes for a small type, every wire type through a
// serialize -> deserialize -> serialize cycle, and precise errors for malformed input.
#include <gtest/gtest.h>

#include <vector>

#include "semfuse/dds/cdr.hpp"
#include "wire_fill.hpp"
#include "wire_types.hpp"

namespace semfuse::dds {
namespace {

using Bytes = std::vector<uint8_t>;

TEST(Cdr, TimeHasHeaderThenLittleEndianFields) {
  Sample<builtin_interfaces_msg_dds__Time_> t;
  t->sec = -2;               // fe ff ff ff
  t->nanosec = 0x01020304u;  // 04 03 02 01
  EXPECT_EQ(serialize(*t), (Bytes{0x00, 0x01, 0x00, 0x00, 0xfe, 0xff, 0xff, 0xff, 0x04, 0x03, 0x02, 0x01}));
}

TEST(Cdr, PaddingToFourBytesIsAnnouncedInTheOptions) {
  Sample<std_msgs_msg_dds__Header_> h;
  h->stamp.sec = 1;
  h->stamp.nanosec = 2;
  setString(h->frame_id, "ab");  // length 3 incl. NUL: body is 15 bytes, 1 byte of padding
  const Bytes expected{0x00, 0x01, 0x00, 0x01, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 'a', 'b', 0, 0};
  EXPECT_EQ(serialize(*h), expected);
}

TEST(Cdr, EveryWireTypeSurvivesDeserializeAndReserialize) {
  int checked = 0;
  testing::forEachWireType([&](auto tag) {
    using T = typename decltype(tag)::type;
    const auto original = testing::filledSample<T>(static_cast<uint32_t>(checked + 1));
    const Bytes bytes = serialize(*original);
    auto decoded = deserialize<T>(bytes);
    ASSERT_TRUE(decoded.ok()) << descriptorOf<T>().m_typename << ": " << decoded.error();
    EXPECT_EQ(serialize(*decoded.value()), bytes) << descriptorOf<T>().m_typename;
    ++checked;
  });
  EXPECT_EQ(checked, testing::kWireTypeCount);
}

TEST(Cdr, DecodedFieldsHaveTheWrittenValues) {
  auto frame = testing::filledSample<semfuse_msg_dds__Frame_>(7);
  auto decoded = deserialize<semfuse_msg_dds__Frame_>(serialize(*frame));
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const auto& d = *decoded.value();
  EXPECT_STREQ(d.camera_id, frame->camera_id);
  EXPECT_EQ(d.seq, frame->seq);
  EXPECT_EQ(d.intrinsics.fx, frame->intrinsics.fx);
  ASSERT_EQ(d.depth._length, frame->depth._length);
  EXPECT_EQ(Bytes(d.depth._buffer, d.depth._buffer + d.depth._length),
            Bytes(frame->depth._buffer, frame->depth._buffer + frame->depth._length));
  EXPECT_EQ(d.camera_to_world[11], frame->camera_to_world[11]);
}

TEST(Cdr, BigEndianInputIsAccepted) {
  const Bytes big{0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xfe, 0x01, 0x02, 0x03, 0x04};
  auto t = deserialize<builtin_interfaces_msg_dds__Time_>(big);
  ASSERT_TRUE(t.ok()) << t.error();
  EXPECT_EQ(t.value()->sec, -2);
  EXPECT_EQ(t.value()->nanosec, 0x01020304u);
}

TEST(Cdr, ShortInputIsRejected) {
  auto r = deserialize<builtin_interfaces_msg_dds__Time_>(Bytes{0x00, 0x01});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("shorter than the 4-byte CDR header"), std::string::npos) << r.error();
}

TEST(Cdr, HeaderWithoutBodyIsRejected) {  // found by fuzz/targets/frame_cdr.cpp (UBSan)
  auto r = deserialize<semfuse_msg_dds__Frame_>(Bytes{0x00, 0x00, 0x0c, 0x00});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("no CDR body after the header"), std::string::npos) << r.error();
}

TEST(Cdr, UnknownEncapsulationIsRejected) {
  auto r = deserialize<builtin_interfaces_msg_dds__Time_>(Bytes{0x00, 0x07, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("unsupported encapsulation 00 07"), std::string::npos) << r.error();
}

TEST(Cdr, TruncatedBodyIsRejected) {
  const auto image = testing::filledSample<sensor_msgs_msg_dds__Image_>(3);
  Bytes bytes = serialize(*image);
  bytes.resize(bytes.size() - 6);  // cuts into the data sequence
  auto r = deserialize<sensor_msgs_msg_dds__Image_>(bytes);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("sensor_msgs::msg::dds_::Image_: malformed CDR"), std::string::npos) << r.error();
}

TEST(Cdr, SequenceCountBeyondTheBufferIsRejected) {
  // Header_ with empty frame_id, then a CompressedImage format "" and a data count of 1e6.
  const Bytes bytes{0x00, 0x01, 0, 0, 1, 0, 0, 0, 2, 0, 0,    0,    1,    0,    0, 0, 0, 0,
                    0,    0,    1, 0, 0, 0, 0, 0, 0, 0, 0x40, 0x42, 0x0f, 0x00, 9, 9, 9, 9};
  auto r = deserialize<sensor_msgs_msg_dds__CompressedImage_>(bytes);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("malformed CDR"), std::string::npos) << r.error();
}

TEST(Cdr, TrailingGarbageIsRejected) {
  Bytes bytes = serialize(*testing::filledSample<builtin_interfaces_msg_dds__Time_>(1));
  bytes.insert(bytes.end(), {1, 2, 3, 4, 5, 6, 7, 8});
  auto r = deserialize<builtin_interfaces_msg_dds__Time_>(bytes);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("8 trailing bytes"), std::string::npos) << r.error();
}

}  // namespace
}  // namespace semfuse::dds
