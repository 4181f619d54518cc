// Fuzz target: a serialized sensor_msgs/CompressedImage -> CDR decoding ->
// wire::compressedImageToMat (format string, PNG header check, OpenCV's PNG / JPEG decoders) and
// wire::compressedDepthToMetres (compressedDepth's format string and configuration header, PNG
// and RVL payloads, inverse depth): the colour and the compressed depth inputs of the server.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "fuzz_support.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/ros_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto sample = semfuse::dds::deserialize<sensor_msgs_msg_dds__CompressedImage_>(data, size);
  if (!sample) return 0;
  if (auto image = semfuse::wire::compressedImageToMat(*sample.value())) {
    SEMFUSE_FUZZ_CHECK(image.value().cols <= static_cast<int>(semfuse::kMaxImageSide));
    SEMFUSE_FUZZ_CHECK(image.value().rows <= static_cast<int>(semfuse::kMaxImageSide));
  }
  if (auto depth = semfuse::wire::compressedDepthToMetres(*sample.value())) {
    const cv::Mat& metres = depth.value();
    SEMFUSE_FUZZ_CHECK(metres.type() == CV_32FC1 && !metres.empty());
    SEMFUSE_FUZZ_CHECK(metres.cols <= static_cast<int>(semfuse::kMaxImageSide));
    SEMFUSE_FUZZ_CHECK(metres.rows <= static_cast<int>(semfuse::kMaxImageSide));
    // What reaches the assembler is metres or 0 (no depth), never negative, infinite or NaN.
    for (int y = 0; y < metres.rows; ++y) {
      for (int x = 0; x < metres.cols; ++x) {
        const float v = metres.at<float>(y, x);
        SEMFUSE_FUZZ_CHECK(std::isfinite(v) && v >= 0.0f);
      }
    }
  }
  return 0;
}
