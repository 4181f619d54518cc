// ROS 2 wire compatibility: the bytes semfuse puts on the wire for sensor_msgs/Image,
// sensor_msgs/CameraInfo and nav_msgs/OccupancyGrid equal the CDR layout ROS 2 defines for them (XCDR1, little
// endian: header 00 01, alignment counted from the first byte after the 4-byte header,
// strings as uint32 length incl. NUL + bytes + NUL, sequences as uint32 count + elements,
// fixed arrays inline). The expected bytes are written out from the .msg definitions.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "semfuse/dds/cdr.hpp"

namespace semfuse::dds {
namespace {

using Bytes = std::vector<uint8_t>;

// Little-endian appenders for the expected layout; padding is always written explicitly.
void u32(Bytes& b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void f64(Bytes& b, double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, 8);
  for (int i = 0; i < 8; ++i) b.push_back(static_cast<uint8_t>(bits >> (8 * i)));
}
void zeros(Bytes& b, std::size_t n) { b.insert(b.end(), n, 0); }
void chars(Bytes& b, const char* s) { b.insert(b.end(), s, s + std::strlen(s) + 1); }

TEST(Ros2Wire, ImageBytesMatchTheRos2Layout) {
  Sample<sensor_msgs_msg_dds__Image_> image;
  image->header.stamp.sec = 1234;
  image->header.stamp.nanosec = 5678;
  setString(image->header.frame_id, "cam");
  image->height = 2;
  image->width = 4;
  setString(image->encoding, "mono8");
  image->is_bigendian = 0;
  image->step = 4;
  const uint8_t pixels[8] = {10, 20, 30, 40, 50, 60, 70, 80};
  setSequence(image->data, pixels, 8);

  const Bytes expected{0x00, 0x01, 0x00, 0x00,                                  // encapsulation: CDR_LE, no padding
                       0xd2, 0x04, 0x00, 0x00,                                  //  0 header.stamp.sec = 1234
                       0x2e, 0x16, 0x00, 0x00,                                  //  4 header.stamp.nanosec = 5678
                       0x04, 0x00, 0x00, 0x00, 'c', 'a', 'm', 0x00,             //  8 header.frame_id = "cam"
                       0x02, 0x00, 0x00, 0x00,                                  // 16 height = 2
                       0x04, 0x00, 0x00, 0x00,                                  // 20 width = 4
                       0x06, 0x00, 0x00, 0x00, 'm', 'o', 'n', 'o',  '8', 0x00,  // 24 encoding = "mono8"
                       0x00,                                                    // 34 is_bigendian = 0
                       0x00,                                                    // 35 padding: step is 4-aligned
                       0x04, 0x00, 0x00, 0x00,                                  // 36 step = 4
                       0x08, 0x00, 0x00, 0x00,                                  // 40 data: 8 elements
                       10,   20,   30,   40,   50,  60,  70,  80};              // 44 data, body ends at 52
  EXPECT_EQ(serialize(*image), expected);

  auto decoded = deserialize<sensor_msgs_msg_dds__Image_>(expected);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_STREQ(decoded.value()->encoding, "mono8");
  EXPECT_EQ(decoded.value()->data._buffer[7], 80);
}

// CameraInfo with the usual plumb_bob model. Its body always ends one byte past a 4-byte
// boundary (roi.do_rectify), so 3 padding bytes follow; XTypes 1.3 has the writer announce
// them in the low bits of the options word, which is what Cyclone (and Fast DDS 2.x) put on the
// wire. Older ROS 2 stacks leave the options 0; such bytes must decode as well.
Bytes expectedCameraInfo(uint8_t options) {
  Bytes b{0x00, 0x01, 0x00, options};
  u32(b, 100);                                        //   0 header.stamp.sec
  u32(b, 200);                                        //   4 header.stamp.nanosec
  u32(b, 8);                                          //   8 header.frame_id length incl. NUL
  chars(b, "optical");                                //  12 "optical\0", ends at 20
  u32(b, 480);                                        //  20 height
  u32(b, 640);                                        //  24 width
  u32(b, 10);                                         //  28 distortion_model length
  chars(b, "plumb_bob");                              //  32 "plumb_bob\0", ends at 42
  zeros(b, 2);                                        //  42 padding to 4
  u32(b, 5);                                          //  44 d: 5 elements
  for (int i = 0; i < 5; ++i) f64(b, 0.1 * (i + 1));  // 48 (8-aligned already) .. 88
  for (int i = 0; i < 9; ++i) f64(b, 1.0 + i);        //  88 k[9] .. 160
  for (int i = 0; i < 9; ++i) f64(b, 20.0 + i);       // 160 r[9] .. 232
  for (int i = 0; i < 12; ++i) f64(b, 40.0 + i);      // 232 p[12] .. 328
  u32(b, 1);                                          // 328 binning_x
  u32(b, 2);                                          // 332 binning_y
  u32(b, 11);                                         // 336 roi.x_offset
  u32(b, 12);                                         // 340 roi.y_offset
  u32(b, 13);                                         // 344 roi.height
  u32(b, 14);                                         // 348 roi.width
  b.push_back(1);                                     // 352 roi.do_rectify = true, body ends at 353
  zeros(b, 3);                                        // padding to a multiple of 4
  return b;
}

TEST(Ros2Wire, CameraInfoBytesMatchTheRos2Layout) {
  Sample<sensor_msgs_msg_dds__CameraInfo_> info;
  info->header.stamp.sec = 100;
  info->header.stamp.nanosec = 200;
  setString(info->header.frame_id, "optical");
  info->height = 480;
  info->width = 640;
  setString(info->distortion_model, "plumb_bob");
  double d[5];
  for (int i = 0; i < 5; ++i) d[i] = 0.1 * (i + 1);
  setSequence(info->d, d, 5);
  for (int i = 0; i < 9; ++i) info->k[i] = 1.0 + i;
  for (int i = 0; i < 9; ++i) info->r[i] = 20.0 + i;
  for (int i = 0; i < 12; ++i) info->p[i] = 40.0 + i;
  info->binning_x = 1;
  info->binning_y = 2;
  info->roi = {11, 12, 13, 14, true};

  const Bytes expected = expectedCameraInfo(0x03);
  ASSERT_EQ(expected.size(), 4u + 356u);
  EXPECT_EQ(serialize(*info), expected);
}

TEST(Ros2Wire, CameraInfoWithoutAnnouncedPaddingDecodes) {
  auto decoded = deserialize<sensor_msgs_msg_dds__CameraInfo_>(expectedCameraInfo(0x00));
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  const auto& info = *decoded.value();
  EXPECT_STREQ(info.header.frame_id, "optical");
  EXPECT_STREQ(info.distortion_model, "plumb_bob");
  ASSERT_EQ(info.d._length, 5u);
  EXPECT_DOUBLE_EQ(info.d._buffer[4], 0.5);
  EXPECT_EQ(info.k[8], 9.0);
  EXPECT_EQ(info.p[11], 51.0);
  EXPECT_EQ(info.roi.width, 14u);
  EXPECT_TRUE(info.roi.do_rectify);
}

// nav_msgs/OccupancyGrid as the occupancy topic and the occupancy_slice reply carry it: the
// header, MapMetaData (time, float32 resolution, sizes, then the origin pose, whose doubles align
// to 8), int8 cells. 106 bytes of body, padded to 108 (announced in the options).
TEST(Ros2Wire, OccupancyGridBytesMatchTheRos2Layout) {
  Sample<nav_msgs_msg_dds__OccupancyGrid_> grid;
  grid->header.stamp.sec = 7;
  grid->header.stamp.nanosec = 8;
  setString(grid->header.frame_id, "map");
  grid->info.map_load_time = {9, 10};
  grid->info.resolution = 0.05f;
  grid->info.width = 3;
  grid->info.height = 2;
  grid->info.origin.position = {-1.25, 2.5, 0.375};
  grid->info.origin.orientation = {0.0, 0.0, 0.0, 1.0};
  const int8_t cells[6] = {0, 100, -1, 99, 0, 0};
  setSequence(grid->data, cells, 6);

  Bytes expected{0x00, 0x01, 0x00, 0x02};
  u32(expected, 7);        //   0 header.stamp.sec
  u32(expected, 8);        //   4 header.stamp.nanosec
  u32(expected, 4);        //   8 header.frame_id length incl. NUL
  chars(expected, "map");  // 12 "map\0", ends at 16
  u32(expected, 9);        //  16 info.map_load_time.sec
  u32(expected, 10);       //  20 info.map_load_time.nanosec
  const float resolution = 0.05f;
  uint32_t resolution_bits;
  std::memcpy(&resolution_bits, &resolution, 4);
  u32(expected, resolution_bits);  // 24 info.resolution (float32)
  u32(expected, 3);                // 28 info.width
  u32(expected, 2);                // 32 info.height
  zeros(expected, 4);              // 36 padding: the pose's doubles align to 8
  for (double v : {-1.25, 2.5, 0.375, 0.0, 0.0, 0.0, 1.0}) f64(expected, v);  // 40 .. 96 origin
  u32(expected, 6);                                                           // 96 data: 6 cells
  for (int8_t c : cells) expected.push_back(static_cast<uint8_t>(c));         // 100 .. 106
  zeros(expected, 2);                                                         // padding to 108
  EXPECT_EQ(serialize(*grid), expected);

  auto decoded = deserialize<nav_msgs_msg_dds__OccupancyGrid_>(expected);
  ASSERT_TRUE(decoded.ok()) << decoded.error();
  EXPECT_STREQ(decoded.value()->header.frame_id, "map");
  EXPECT_EQ(decoded.value()->info.height, 2u);
  EXPECT_EQ(decoded.value()->info.origin.position.z, 0.375);
  EXPECT_EQ(decoded.value()->data._buffer[2], -1);
}

}  // namespace
}  // namespace semfuse::dds
