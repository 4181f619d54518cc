// Fuzz target: the text files of a 7-Scenes folder. First byte even: camera-intrinsics.txt
// (readSevenScenesIntrinsics), odd: frame-NNNNNN.pose.txt (readSevenScenesPose); the rest is the
// file. What is accepted must be finite (the camera sends it on as it is).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "semfuse/datasets/seven_scenes.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const bool pose_file = data[0] % 2 == 1;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  if (pose_file) {
    const auto path = semfuse::fuzz::writeScratchFile("frame-000000.pose.txt", text);
    if (auto pose = semfuse::datasets::readSevenScenesPose(path)) {
      SEMFUSE_FUZZ_CHECK(pose.value().matrix().allFinite());
    }
  } else {
    const auto path = semfuse::fuzz::writeScratchFile("camera-intrinsics.txt", text);
    if (auto k = semfuse::datasets::readSevenScenesIntrinsics(path)) {
      SEMFUSE_FUZZ_CHECK(k.value().fx > 0.0 && k.value().fy > 0.0);
    }
  }
  return 0;
}
