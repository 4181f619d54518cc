#pragma once
// cv::Mat <-> the sensor_msgs/Image members of DDS samples (the raycast reply's layers), both
// directions. Decoding checks the image like any other input: a server of another version, or a
// damaged one, gets an error, never a crash.
#include <cstdint>

#include <opencv2/core/mat.hpp>

#include <sensor_msgs.h>

#include "semfuse/core/result.hpp"

namespace semfuse::wire {

// Copies `image` into `out`: width, height, step, little-endian, `encoding` (e.g. "32FC1"),
// frame_id and the pixel rows, in buffers dds_alloc'd for it and freed with the sample. An empty
// image leaves `out` as it is (a layer that was not asked for stays empty).
void fillImageMessage(sensor_msgs_msg_dds__Image_& out, const cv::Mat& image, const char* encoding,
                      const char* frame_id = "camera");

// Larger sides than any raycast a server answers (its --max-raycast-pixels is far below 65536^2);
// also keeps every size computation of the decoders far from overflow.
inline constexpr uint32_t kMaxImageMessageSide = 1u << 16;

// Image_ -> cv::Mat for the encodings raycast replies use (32FC1, 32FC3, 16UC1 / mono16, 8UC1 /
// mono8, rgb8, bgr8 (swapped to RGB), 8UC3); an image without pixels (a layer not requested)
// gives an empty Mat. Rows are copied with the message's step.
Result<cv::Mat> decodeImageMessage(const sensor_msgs_msg_dds__Image_& image);
// The same, without copying where it can: the Mat takes over the sample's pixel buffer (the
// sample's data sequence is left empty). A raycast reply is 5.5 MB at 640x480 with depth, normals
// and labels; copying it into fresh Mats took ~3.6 ms of each reply in semfuse-bench ingest.
// BGR images and buffers the sample does not own are copied as decodeImageMessage does.
Result<cv::Mat> takeImageMessage(sensor_msgs_msg_dds__Image_& image);

}  // namespace semfuse::wire
