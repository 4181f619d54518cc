#pragma once
// What semfuse-viewer sends the page over its WebSocket (viewer.js reads the same layouts).
//
// Binary messages, little-endian, starting with a uint32 kind:
//   kBlock:   kind, origin x y z (int32, voxels), vertex count V, triangle count T, own vertex
//             count (uint32; vertices [0, own) are the block's, the rest repeat its neighbours'), then
//             float32 positions [3V] (world, metres), float32 scores [V], uint32 indices [3T],
//             uint16 labels [V] (padded to 4 bytes), uint8 RGB [3V] (zero when the map has no colour)
//   kRemoved: kind, origin x y z: the block's surface is gone
//   kCleared: kind: every block is gone (the map was cleared or replaced, or a new server run)
//   kRaycast: kind, then a PNG: the server's raycast from the page's view, labels in legend colours
// Text messages are JSON objects with a "type": "legend", "status", "poses", "labels_at".
#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/client/map_follower.hpp"
#include "semfuse/client/server_status.hpp"
#include "semfuse/core/json_text.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::viewer {

enum class BlockMessage : uint32_t { kBlock = 1, kRemoved = 2, kCleared = 3, kRaycast = 4 };

std::string blockMessage(const MeshBlock& block, double voxel_size);
std::string removedMessage(const BlockOrigin& origin);
std::string clearedMessage();
// Labels (CV_16UC1) in legend colours, black where the ray met nothing (depth 0), as a PNG.
std::string raycastMessage(const RaycastImages& view, const LabelLegend& legend);

std::string legendJson(const LabelLegend& legend);

// What the viewer itself counts, shown beside the server's counters.
struct FollowerCounters {
  std::size_t blocks = 0;
  std::size_t vertices = 0;
  uint64_t revision = 0;
  uint64_t updates = 0;
  uint64_t catch_ups = 0;
  uint64_t gaps = 0;
  std::size_t browsers = 0;
};
std::string statusJson(const std::optional<ServerStatus>& status, const FollowerCounters& follower);

// A camera's poses as the page draws them: camera-to-world 4x4 (column-major, as three.js takes
// it), tracking state, whether the frame was integrated.
std::string posesJson(const std::vector<TrackedPose>& poses);

// `object`: the instance of the sample's label (the objects service) around the point, if any.
std::string labelsAtJson(const Eigen::Vector3d& point, const VoxelSample& sample, const LabelLegend& legend,
                         const ObjectInstance* object = nullptr);
std::string errorJson(const std::string& what, const std::string& message);

}  // namespace semfuse::viewer
