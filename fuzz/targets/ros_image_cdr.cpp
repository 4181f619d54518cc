// Fuzz target: a serialized sensor_msgs/Image (as a ROS 2 camera publishes it) -> CDR
// decoding -> wire::imageToMat and wire::depthImageToMetres (encodings, step, size, endianness).
#include <cstddef>
#include <cstdint>

#include <opencv2/core.hpp>

#include "fuzz_support.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/ros_codec.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto sample = semfuse::dds::deserialize<sensor_msgs_msg_dds__Image_>(data, size);
  if (!sample) return 0;
  const auto& msg = *sample.value();
  if (auto image = semfuse::wire::imageToMat(msg)) {
    SEMFUSE_FUZZ_CHECK(image.value().cols == static_cast<int>(msg.width));
    SEMFUSE_FUZZ_CHECK(image.value().rows == static_cast<int>(msg.height));
  }
  if (auto depth = semfuse::wire::depthImageToMetres(msg)) {
    SEMFUSE_FUZZ_CHECK(depth.value().type() == CV_32FC1);
  }
  return 0;
}
