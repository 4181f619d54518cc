// Fuzz target: a serialized sensor_msgs/CompressedImage -> CDR decoding ->
// wire::compressedImageToMat (format string, PNG header check, OpenCV's PNG / JPEG decoders).
#include <cstddef>
#include <cstdint>

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
  return 0;
}
