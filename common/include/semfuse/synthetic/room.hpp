#pragma once
// The built-in procedural room: floor, four walls, optional ceiling, a table, two chairs, boxes,
// spheres and a cabinet. World frame: z up, floor at z = 0, room centred on the origin.
// Every solid knows its object instance (SceneObject::instance): the table's top and legs are one,
// each chair's seat, back and legs are one, the four walls are one; every other solid is its own.
#include <cstdint>

#include "semfuse/core/legend.hpp"
#include "semfuse/synthetic/labeled_scene.hpp"

namespace semfuse::synthetic {

// Label ids of the room, fixed: builtinLegend("synthetic") names exactly these.
namespace labels {
inline constexpr LabelId kFloor = 1;
inline constexpr LabelId kWall = 2;
inline constexpr LabelId kCeiling = 3;
inline constexpr LabelId kTable = 4;
inline constexpr LabelId kChair = 5;
inline constexpr LabelId kBox = 6;
inline constexpr LabelId kSphere = 7;
inline constexpr LabelId kCabinet = 8;
inline constexpr LabelId kMax = kCabinet;
}  // namespace labels

struct RoomOptions {
  double size_x = 5.0;  // inner extent along x, metres (walls at x = +-size_x / 2)
  double size_y = 4.0;  // inner extent along y (walls at y = +-size_y / 2)
  double height = 2.6;  // ceiling height / wall height
  bool ceiling = true;  // without it, rays leaving over the walls see nothing (depth 0)
  uint64_t seed = 0;    // texture variation only; the layout is fixed so tests can rely on it
};

// Furniture is placed for the default size; the room must be at least 4.6 x 3.6 x 2.0 m so that
// nothing pokes through a wall. Walls, floor and ceiling are 0.2 m thick slabs outside the room.
LabeledScene makeRoom(const RoomOptions& options = {});

}  // namespace semfuse::synthetic
