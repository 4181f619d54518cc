#pragma once
// Writes a raycast reply to a folder: PNGs to look at (colourised depth, normals, labels with the
// legend's colours, confidence as grey, colour) and lossless files to compute with (16-bit label
// and millimetre depth PNGs, 32-bit float TIFFs of depth, normals and confidence).
#include <filesystem>
#include <string>
#include <vector>

#include "semfuse/client/map_client.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"

namespace semfuse::tools {

// Returns the files written.
Result<std::vector<std::filesystem::path>> writeRaycastImages(const client::RaycastImages& images,
                                                              const LabelLegend& legend,
                                                              const std::filesystem::path& folder);

}  // namespace semfuse::tools
