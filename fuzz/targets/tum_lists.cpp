// Fuzz target: the list files of a TUM RGB-D folder, read by TumRgbdReader::open (intrinsics
// given, so the folder name does not matter). The input holds the files one after the other,
// separated by a line "=====": depth.txt, rgb.txt and, when a third part is there,
// groundtruth.txt. Images are not read (no frame is loaded): only the list parsing and the
// association of depth, colour and poses in time.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "fuzz_support.hpp"
#include "semfuse/datasets/tum_rgbd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  const std::string_view separator = "\n=====\n";
  const std::string_view depth = semfuse::fuzz::nextPart(rest, separator);
  const bool has_color = !rest.empty();
  const std::string_view color = semfuse::fuzz::nextPart(rest, separator);
  const bool has_ground_truth = !rest.empty();
  const std::string_view ground_truth = rest;

  const std::filesystem::path folder = semfuse::fuzz::scratchFolder() / "tum";
  std::filesystem::create_directories(folder);
  std::error_code ignored;
  for (const char* name : {"depth.txt", "rgb.txt", "groundtruth.txt"}) std::filesystem::remove(folder / name, ignored);
  semfuse::fuzz::writeScratchFile("tum/depth.txt", depth);
  if (has_color) semfuse::fuzz::writeScratchFile("tum/rgb.txt", color);
  if (has_ground_truth) semfuse::fuzz::writeScratchFile("tum/groundtruth.txt", ground_truth);

  semfuse::datasets::TumRgbdOptions options;
  options.intrinsics = semfuse::PinholeIntrinsics{640, 480, 525.0, 525.0, 319.5, 239.5};
  auto reader = semfuse::datasets::TumRgbdReader::open(folder, options);
  if (!reader) return 0;
  SEMFUSE_FUZZ_CHECK(reader.value().count() > 0);
  for (std::size_t i = 0; i < reader.value().count(); ++i) {
    const auto& entry = reader.value().entry(i);
    if (entry.camera_to_world) SEMFUSE_FUZZ_CHECK(entry.camera_to_world->matrix().allFinite());
  }
  return 0;
}
