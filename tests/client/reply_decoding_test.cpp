// The client's checks of server replies (client/src/reply_decoding.*): images whose declared size
// the data cannot hold or no client could allocate, and mesh chunks that do not add up.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cstring>
#include <string>

#include "reply_decoding.hpp"
#include "semfuse/dds/sample.hpp"

namespace semfuse::client::detail {
namespace {

void fill(sensor_msgs_msg_dds__Image_& image, uint32_t width, uint32_t height, const char* encoding,
          std::size_t data_bytes) {
  image.width = width;
  image.height = height;
  image.step = 0;
  dds::setString(image.encoding, encoding);
  dds::resizeSequence(image.data, data_bytes);
  for (std::size_t i = 0; i < data_bytes; ++i) image.data._buffer[i] = static_cast<uint8_t>(i);
}

TEST(ReplyDecoding, ImageIsCopiedRowByRowWithItsStep) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 2, 3, "16UC1", 3 * 6);
  image->step = 6;  // 4 bytes of pixels and 2 of padding per row
  auto mat = decodeImage(*image);
  ASSERT_TRUE(mat.ok()) << mat.error();
  ASSERT_EQ(mat.value().rows, 3);
  ASSERT_EQ(mat.value().cols, 2);
  uint16_t expected;
  std::memcpy(&expected, image->data._buffer + 2 * 6 + 2, 2);  // row 2, column 1
  EXPECT_EQ(mat.value().at<uint16_t>(2, 1), expected);
}

TEST(ReplyDecoding, ImageLargerThanItsDataIsRefused) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 4, 3, "32FC1", 4 * 3 * 4 - 1);
  auto mat = decodeImage(*image);
  ASSERT_FALSE(mat.ok());
  EXPECT_NE(mat.error().find("shorter"), std::string::npos) << mat.error();
}

TEST(ReplyDecoding, ImageSidesBeyondAnyRaycastAreRefusedBeforeAnySizeArithmetic) {
  // A side of 2^31 or more became a negative int; a height of 2^31 made the size check compute
  // INT_MIN - 1 (undefined behaviour).
  for (uint32_t side : {kMaxImageSide + 1, 1u << 31, UINT32_MAX}) {
    dds::Sample<sensor_msgs_msg_dds__Image_> wide, tall;
    fill(*wide, side, 1, "32FC3", 16);
    fill(*tall, 1, side, "32FC3", 16);
    for (const auto* image : {&*wide, &*tall}) {
      auto mat = decodeImage(*image);
      ASSERT_FALSE(mat.ok()) << side;
      EXPECT_NE(mat.error().find("exceeds"), std::string::npos) << mat.error();
    }
  }
}

TEST(ReplyDecoding, TakenImageKeepsTheSamplesPixelsWithoutACopy) {
  cv::Mat mat;
  const uint8_t* pixels = nullptr;
  {
    dds::Sample<sensor_msgs_msg_dds__Image_> image;
    fill(*image, 4, 3, "32FC1", 4 * 3 * 4);
    pixels = image->data._buffer;
    auto taken = takeImage(*image);
    ASSERT_TRUE(taken.ok()) << taken.error();
    mat = taken.value();
    EXPECT_EQ(mat.data, pixels);  // the same buffer, not a copy
    EXPECT_EQ(image->data._buffer, nullptr);
    EXPECT_EQ(image->data._length, 0u);
    EXPECT_FALSE(image->data._release);
  }  // the sample is freed; the pixels live on in the Mat
  ASSERT_EQ(mat.rows, 3);
  ASSERT_EQ(mat.cols, 4);
  float expected;
  const uint8_t bytes[4] = {4 * 9 + 0, 4 * 9 + 1, 4 * 9 + 2, 4 * 9 + 3};  // pixel (2, 1) is float 9
  std::memcpy(&expected, bytes, 4);
  EXPECT_EQ(mat.at<float>(2, 1), expected);
  // Shared like any Mat: the last one to go frees the buffer (ASan builds check that it is freed
  // once); create() to another size takes fresh memory from OpenCV.
  cv::Mat shared = mat;
  mat.release();
  EXPECT_EQ(shared.at<float>(2, 1), expected);
  shared.create(5, 5, CV_32FC1);
  shared.setTo(1.0f);
  EXPECT_EQ(shared.at<float>(4, 4), 1.0f);
}

TEST(ReplyDecoding, TakenBgrOrUnownedImagesAreCopied) {
  dds::Sample<sensor_msgs_msg_dds__Image_> bgr;
  fill(*bgr, 2, 1, "bgr8", 6);  // bytes 0 1 2 | 3 4 5
  auto swapped = takeImage(*bgr);
  ASSERT_TRUE(swapped.ok()) << swapped.error();
  EXPECT_NE(bgr->data._buffer, nullptr);  // still the sample's
  EXPECT_EQ(swapped.value().at<cv::Vec3b>(0, 1), cv::Vec3b(5, 4, 3));

  dds::Sample<sensor_msgs_msg_dds__Image_> lent;
  fill(*lent, 2, 2, "16UC1", 8);
  lent->data._release = false;  // a buffer the sample does not own
  uint8_t* buffer = lent->data._buffer;
  auto copied = takeImage(*lent);
  ASSERT_TRUE(copied.ok()) << copied.error();
  EXPECT_NE(copied.value().data, buffer);
  EXPECT_EQ(lent->data._buffer, buffer);
  lent->data._release = true;  // so that the sample frees it after all
}

TEST(ReplyDecoding, TakenImageIsCheckedLikeADecodedOne) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 4, 3, "32FC1", 4 * 3 * 4 - 1);
  auto taken = takeImage(*image);
  ASSERT_FALSE(taken.ok());
  EXPECT_NE(taken.error().find("shorter"), std::string::npos) << taken.error();
  EXPECT_NE(image->data._buffer, nullptr);
}

void fillChunk(semfuse_srv_dds__Mesh_Response_& reply, uint64_t mesh_id, uint32_t index, uint32_t count, uint64_t total,
               const std::string& bytes) {
  reply.mesh_id = mesh_id;
  reply.chunk_index = index;
  reply.chunk_count = count;
  reply.total_bytes = total;
  dds::setSequence(reply.ply, reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

TEST(ReplyDecoding, MeshChunksJoinInOrder) {
  dds::Sample<semfuse_srv_dds__Mesh_Response_> first, second;
  fillChunk(*first, 9, 0, 2, 7, "ply\n");
  fillChunk(*second, 9, 1, 2, 7, "end");
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(*first, 0).ok());
  EXPECT_EQ(assembly.chunkCount(), 2u);
  EXPECT_EQ(assembly.meshId(), 9u);
  ASSERT_TRUE(assembly.add(*second, 1).ok());
  auto mesh = std::move(assembly).finish();
  ASSERT_TRUE(mesh.ok()) << mesh.error();
  EXPECT_EQ(std::string(mesh.value().ply.begin(), mesh.value().ply.end()), "ply\nend");
}

TEST(ReplyDecoding, MeshChunksThatDoNotBelongAreRefused) {
  dds::Sample<semfuse_srv_dds__Mesh_Response_> first, other_mesh, too_long;
  fillChunk(*first, 9, 0, 2, 7, "ply\n");
  fillChunk(*other_mesh, 10, 1, 2, 7, "end");
  fillChunk(*too_long, 9, 1, 2, 7, "end and more");
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(*first, 0).ok());
  const Status wrong_mesh = assembly.add(*other_mesh, 1);
  ASSERT_FALSE(wrong_mesh.ok());
  EXPECT_NE(wrong_mesh.error().find("of mesh 10"), std::string::npos) << wrong_mesh.error();
  const Status overflow = assembly.add(*too_long, 1);
  ASSERT_FALSE(overflow.ok());
  EXPECT_NE(overflow.error().find("more than the 7 bytes"), std::string::npos) << overflow.error();
  auto incomplete = std::move(assembly).finish();
  ASSERT_FALSE(incomplete.ok());
  EXPECT_NE(incomplete.error().find("1 of 2 chunks"), std::string::npos) << incomplete.error();
}

TEST(ReplyDecoding, AnAbsurdAnnouncedMeshSizeIsNotAllocated) {
  // A reply announcing 2^60 bytes in one 4-byte chunk once made the client reserve them
  // (std::bad_alloc thrown out of MapClient::mesh).
  dds::Sample<semfuse_srv_dds__Mesh_Response_> reply;
  fillChunk(*reply, 1, 0, 1, uint64_t{1} << 60, "ply\n");
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(*reply, 0).ok());
  auto mesh = std::move(assembly).finish();
  ASSERT_FALSE(mesh.ok());
  EXPECT_NE(mesh.error().find("server announced"), std::string::npos) << mesh.error();
}

TEST(ReplyDecoding, ManyAnnouncedChunksDoNotMakeTheClientReserveGigabytes) {
  // 2^32 - 1 chunks of 64 bytes and a total to match: the first fix still reserved 4 GB (fuzzer).
  dds::Sample<semfuse_srv_dds__Mesh_Response_> reply;
  fillChunk(*reply, 1, 0, UINT32_MAX, uint64_t{64} * UINT32_MAX, std::string(64, 'x'));
  MeshAssembly assembly;
  ASSERT_TRUE(assembly.add(*reply, 0).ok());
  EXPECT_EQ(assembly.chunkCount(), UINT32_MAX);
  EXPECT_LE(assembly.reservedBytes(), kMaxMeshReserveBytes);
  EXPECT_GE(assembly.reservedBytes(), 64u);
}

}  // namespace
}  // namespace semfuse::client::detail
