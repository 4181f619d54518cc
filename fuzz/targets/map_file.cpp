// Fuzz target: a map file (--map FILE at start-up, the admin LOAD service) -> volume::loadMap:
// the integrity trailer (length, CRC-64) checked over the whole file first, then OpenVDB's stream
// reader, the semfuse metadata, the layer grids and their merge, the voxel checksum. A damaged
// file must be an error that leaves nothing behind; mutated bytes almost never keep the CRC, so
// this exercises the seal, which is what stands between a damaged file and OpenVDB's reader.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_support.hpp"
#include "semfuse/volume/map_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path =
      semfuse::fuzz::writeScratchFile("map.vdb", std::string_view(reinterpret_cast<const char*>(data), size));
  auto map = semfuse::volume::loadMap(path);
  if (!map) return 0;
  SEMFUSE_FUZZ_CHECK(map.value().format_version >= 1 &&
                     map.value().format_version <= semfuse::volume::kMapFormatVersion);
  return 0;
}
