#pragma once
// Conversions between the generated wire structs and the client's C++ types. Private to the
// client library: users of semfuse::client never see a generated C struct.
//
// Frames, segmentations and legends go through common/wire (the codecs the server uses); what
// is here is only what common/wire does not cover: the raycast reply's images (32FC3 normals
// included) and the server status.
#include <opencv2/core/mat.hpp>

#include "semfuse/client/server_status.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/sample.hpp"

namespace semfuse::client::detail {

// sensor_msgs Image_ -> cv::Mat for the encodings raycast replies use (32FC1, 32FC3, 16UC1,
// 8UC1, rgb8, bgr8); an empty image (layer not requested) gives an empty Mat.
Result<cv::Mat> decodeImage(const sensor_msgs_msg_dds__Image_& image);

ServerStatus decodeStatus(const semfuse_msg_dds__ServerStatus_& msg);

}  // namespace semfuse::client::detail
