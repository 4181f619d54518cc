#include "semfuse/wire/image_message.hpp"

#include <cstring>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "semfuse/dds/sample.hpp"

namespace semfuse::wire {
namespace {

TEST(ImageMessage, CopiesPackedRowsOfAnyImage) {
  // A view into a larger image: its rows are not contiguous, the message's must be.
  cv::Mat big(6, 8, CV_32FC3);
  for (int v = 0; v < big.rows; ++v)
    for (int u = 0; u < big.cols; ++u)
      big.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(u), static_cast<float>(v), 1.0f);
  const cv::Mat view = big(cv::Rect(2, 1, 4, 3));
  ASSERT_FALSE(view.isContinuous());
  dds::Sample<sensor_msgs_msg_dds__Image_> msg;
  fillImageMessage(*msg, view, "32FC3");
  EXPECT_EQ(msg->width, 4u);
  EXPECT_EQ(msg->height, 3u);
  EXPECT_EQ(msg->step, 4u * 12u);
  EXPECT_EQ(msg->is_bigendian, 0);
  EXPECT_STREQ(msg->encoding, "32FC3");
  EXPECT_STREQ(msg->header.frame_id, "camera");
  ASSERT_EQ(msg->data._length, 4u * 3u * 12u);
  const cv::Mat packed = view.clone();
  EXPECT_EQ(0, std::memcmp(msg->data._buffer, packed.data, msg->data._length));
  // Filled again (a reused reply): the old buffers are replaced, not leaked (ASan checks).
  fillImageMessage(*msg, cv::Mat(2, 2, CV_16UC1, cv::Scalar(7)), "16UC1", "map");
  EXPECT_EQ(msg->data._length, 8u);
  EXPECT_STREQ(msg->header.frame_id, "map");
}

TEST(ImageMessage, EmptyImageLeavesTheMessageEmpty) {
  dds::Sample<sensor_msgs_msg_dds__Image_> msg;
  fillImageMessage(*msg, cv::Mat(), "32FC1");
  EXPECT_EQ(msg->width, 0u);
  EXPECT_EQ(msg->data._length, 0u);
  EXPECT_EQ(msg->encoding, nullptr);
}

// The decoders check what a server sent like any other input: images whose declared size the
// data cannot hold or no client could allocate.
void fill(sensor_msgs_msg_dds__Image_& image, uint32_t width, uint32_t height, const char* encoding,
          std::size_t data_bytes) {
  image.width = width;
  image.height = height;
  image.step = 0;
  dds::setString(image.encoding, encoding);
  dds::resizeSequence(image.data, data_bytes);
  for (std::size_t i = 0; i < data_bytes; ++i) image.data._buffer[i] = static_cast<uint8_t>(i);
}

TEST(ImageMessage, ImageIsCopiedRowByRowWithItsStep) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 2, 3, "16UC1", 3 * 6);
  image->step = 6;  // 4 bytes of pixels and 2 of padding per row
  auto mat = decodeImageMessage(*image);
  ASSERT_TRUE(mat.ok()) << mat.error();
  ASSERT_EQ(mat.value().rows, 3);
  ASSERT_EQ(mat.value().cols, 2);
  uint16_t expected;
  std::memcpy(&expected, image->data._buffer + 2 * 6 + 2, 2);  // row 2, column 1
  EXPECT_EQ(mat.value().at<uint16_t>(2, 1), expected);
}

TEST(ImageMessage, ImageLargerThanItsDataIsRefused) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 4, 3, "32FC1", 4 * 3 * 4 - 1);
  auto mat = decodeImageMessage(*image);
  ASSERT_FALSE(mat.ok());
  EXPECT_NE(mat.error().find("shorter"), std::string::npos) << mat.error();
}

TEST(ImageMessage, ImageSidesBeyondAnyRaycastAreRefusedBeforeAnySizeArithmetic) {
  // A side of 2^31 or more became a negative int; a height of 2^31 made the size check compute
  // INT_MIN - 1 (undefined behaviour).
  for (uint32_t side : {kMaxImageMessageSide + 1, 1u << 31, UINT32_MAX}) {
    dds::Sample<sensor_msgs_msg_dds__Image_> wide, tall;
    fill(*wide, side, 1, "32FC3", 16);
    fill(*tall, 1, side, "32FC3", 16);
    for (const auto* image : {&*wide, &*tall}) {
      auto mat = decodeImageMessage(*image);
      ASSERT_FALSE(mat.ok()) << side;
      EXPECT_NE(mat.error().find("exceeds"), std::string::npos) << mat.error();
    }
  }
}

TEST(ImageMessage, TakenImageKeepsTheSamplesPixelsWithoutACopy) {
  cv::Mat mat;
  const uint8_t* pixels = nullptr;
  {
    dds::Sample<sensor_msgs_msg_dds__Image_> image;
    fill(*image, 4, 3, "32FC1", 4 * 3 * 4);
    pixels = image->data._buffer;
    auto taken = takeImageMessage(*image);
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

TEST(ImageMessage, TakenBgrOrUnownedImagesAreCopied) {
  dds::Sample<sensor_msgs_msg_dds__Image_> bgr;
  fill(*bgr, 2, 1, "bgr8", 6);  // bytes 0 1 2 | 3 4 5
  auto swapped = takeImageMessage(*bgr);
  ASSERT_TRUE(swapped.ok()) << swapped.error();
  EXPECT_NE(bgr->data._buffer, nullptr);  // still the sample's
  EXPECT_EQ(swapped.value().at<cv::Vec3b>(0, 1), cv::Vec3b(5, 4, 3));

  dds::Sample<sensor_msgs_msg_dds__Image_> lent;
  fill(*lent, 2, 2, "16UC1", 8);
  lent->data._release = false;  // a buffer the sample does not own
  uint8_t* buffer = lent->data._buffer;
  auto copied = takeImageMessage(*lent);
  ASSERT_TRUE(copied.ok()) << copied.error();
  EXPECT_NE(copied.value().data, buffer);
  EXPECT_EQ(lent->data._buffer, buffer);
  lent->data._release = true;  // so that the sample frees it after all
}

TEST(ImageMessage, TakenImageIsCheckedLikeADecodedOne) {
  dds::Sample<sensor_msgs_msg_dds__Image_> image;
  fill(*image, 4, 3, "32FC1", 4 * 3 * 4 - 1);
  auto taken = takeImageMessage(*image);
  ASSERT_FALSE(taken.ok());
  EXPECT_NE(taken.error().find("shorter"), std::string::npos) << taken.error();
  EXPECT_NE(image->data._buffer, nullptr);
}

}  // namespace
}  // namespace semfuse::wire
