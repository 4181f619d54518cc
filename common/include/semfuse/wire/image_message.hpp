#pragma once
// Images into the sensor_msgs/Image members of DDS samples (the raycast reply's layers).
#include <opencv2/core/mat.hpp>

#include <sensor_msgs.h>

namespace semfuse::wire {

// Copies `image` into `out`: width, height, step, little-endian, `encoding` (e.g. "32FC1"),
// frame_id and the pixel rows, in buffers dds_alloc'd for it and freed with the sample. An empty
// image leaves `out` as it is (a layer that was not asked for stays empty).
void fillImageMessage(sensor_msgs_msg_dds__Image_& out, const cv::Mat& image, const char* encoding,
                      const char* frame_id = "camera");

}  // namespace semfuse::wire
