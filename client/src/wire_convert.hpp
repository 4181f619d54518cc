#pragma once
// Conversions between the generated wire structs and the client's C++ types. Private to the
// client library: users of semfuse::client never see a generated C struct.
//
// Why here and not in common/wire: common/wire was not available when the client was written;
// these functions cover exactly what the client needs and can be swapped for common/wire's codecs
// without changing any public header.
#include <opencv2/core/mat.hpp>

#include "semfuse/client/encoding.hpp"
#include "semfuse/client/server_status.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/sample.hpp"

namespace semfuse::client::wire {

struct FrameEncoding {
  DepthEncoding depth = DepthEncoding::kRaw16;
  ColorEncoding color = ColorEncoding::kJpeg;
  int jpeg_quality = 90;
};

// Frame (depth CV_32FC1 metres, colour CV_8UC3 RGB or empty) -> wire sample.
Status encodeFrame(const Frame& frame, const FrameEncoding& encoding,
                   semfuse_msg_dds__Frame_& out);
Result<Frame> decodeFrame(const semfuse_msg_dds__Frame_& msg);

// labels CV_16UC1, confidence CV_32FC1 (or empty = all 1) -> wire, confidence as 8UC1.
Status encodeSegmentation(const Segmentation& segmentation, semfuse_msg_dds__Segmentation_& out);

// sensor_msgs Image_ -> cv::Mat for the encodings raycast replies use (32FC1, 32FC3, 16UC1,
// 8UC1, rgb8, bgr8); an empty image (layer not requested) gives an empty Mat.
Result<cv::Mat> decodeImage(const sensor_msgs_msg_dds__Image_& image);

LabelLegend decodeLegend(const semfuse_msg_dds__LabelLegend_& msg);
ServerStatus decodeStatus(const semfuse_msg_dds__ServerStatus_& msg);

// Row-major 3x4 [R|t] <-> Pose.
void poseToArray(const Pose& pose, double out[12]);
Pose poseFromArray(const double in[12]);

}  // namespace semfuse::client::wire
