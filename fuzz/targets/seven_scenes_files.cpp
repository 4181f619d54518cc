// Fuzz target: the text files of a 7-Scenes folder. First byte even: camera-intrinsics.txt
// (readSevenScenesIntrinsics), odd: frame-NNNNNN.pose.txt (readSevenScenesPose); the rest is the
// file. What is accepted must pass the camera check (the camera sends it on as it is, and the
// server checks it again).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/datasets/seven_scenes.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool pose_file = data[0] % 2 == 1;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (pose_file) {
    const auto path = semfuse::fuzz::writeScratchFile("frame-000000.pose.txt", text);
    if (auto pose = semfuse::datasets::readSevenScenesPose(path)) {
      SEMFUSE_FUZZ_CHECK(semfuse::checkRigidPose(pose.value()).ok());
    }
  } else {
    const auto path = semfuse::fuzz::writeScratchFile("camera-intrinsics.txt", text);
    if (auto k = semfuse::datasets::readSevenScenesIntrinsics(path)) {
      SEMFUSE_FUZZ_CHECK(semfuse::checkProjection(k.value()).ok());
    }
  }
  return 0;
}
