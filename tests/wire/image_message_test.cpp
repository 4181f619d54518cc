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

}  // namespace
}  // namespace semfuse::wire
