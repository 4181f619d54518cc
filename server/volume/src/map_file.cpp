#include "semfuse/volume/map_file.hpp"

namespace semfuse::volume {

Status saveMap(const LabeledVolume&, const LabelLegend&, const std::filesystem::path& path, const MapExtraMetadata&) {
  return makeError("saveMap(" + path.string() + "): map files are not implemented yet");
}

Result<LoadedMap> loadMap(const std::filesystem::path& path) {
  return makeError("loadMap(" + path.string() + "): map files are not implemented yet");
}

}  // namespace semfuse::volume
