#pragma once
// The images a raycast can produce, as bits of one mask: the same values the wire carries
// (Raycast_Request_Constants::LAYER_* in idl/semfuse/srv.idl; common/src/wire/raycast_codec.cpp
// checks them at compile time), the renderer reads and the client library asks for.
#include <cstdint>

namespace semfuse {

enum RaycastLayer : uint32_t {
  kDepthLayer = 1u << 0,       // CV_32FC1, metres along the camera z axis, 0 = no surface
  kNormalsLayer = 1u << 1,     // CV_32FC3, unit normal from the TSDF gradient, world frame, 0 = none
  kLabelsLayer = 1u << 2,      // CV_16UC1, label of the voxel nearest the surface point, 0 = none
  kConfidenceLayer = 1u << 3,  // CV_32FC1, that voxel's label score (Algorithm 1 evidence)
  kColorLayer = 1u << 4,       // CV_8UC3 RGB, that voxel's colour (needs a map with colour)
};
// A combination of RaycastLayer bits (combine with |).
using RaycastLayers = uint32_t;
inline constexpr RaycastLayers kAllLayers = (1u << 5) - 1;

}  // namespace semfuse
