// Fuzz target: the ROS 2 geometry a camera sends with its images. The first byte picks the
// type (0: sensor_msgs/CameraInfo, 1: geometry_msgs/TransformStamped, 2: tf2_msgs/TFMessage),
// the rest is its CDR -> wire::intrinsicsFromCameraInfo / wire::poseFromTransform.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/ros_codec.hpp"

namespace {

void checkTransform(const geometry_msgs_msg_dds__Transform_& transform) {
  auto pose = semfuse::wire::poseFromTransform(transform);
  // A pose accepted from a transform must be accepted everywhere else a pose is checked.
  if (pose) SEMFUSE_FUZZ_CHECK(semfuse::checkRigidPose(pose.value()).ok());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0] % 3;
  ++data;
  --size;
  if (selector == 0) {
    auto sample = semfuse::dds::deserialize<sensor_msgs_msg_dds__CameraInfo_>(data, size);
    if (sample) (void)semfuse::wire::intrinsicsFromCameraInfo(*sample.value());
  } else if (selector == 1) {
    auto sample = semfuse::dds::deserialize<geometry_msgs_msg_dds__TransformStamped_>(data, size);
    if (sample) checkTransform(sample.value()->transform);
  } else {
    auto sample = semfuse::dds::deserialize<tf2_msgs_msg_dds__TFMessage_>(data, size);
    if (!sample) return 0;
    for (uint32_t i = 0; i < sample.value()->transforms._length; ++i) {
      checkTransform(sample.value()->transforms._buffer[i].transform);
    }
  }
  return 0;
}
