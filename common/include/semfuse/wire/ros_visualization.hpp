#pragma once
// The live mesh as ROS 2 visualisation messages, for RViz 2 and Foxglove without a bridge:
// each map block as a visualization_msgs/Marker (TRIANGLE_LIST, one colour per triangle corner)
// in a MarkerArray, and the surface's vertices as a sensor_msgs/PointCloud2 with x, y, z, rgb,
// label and confidence fields. The server publishes both (server/dds/map_update_publisher.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include <sensor_msgs.h>
#include <visualization_msgs.h>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/map_blocks.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::wire {

// What colours a vertex: its label's legend colour (LabelLegend::colorOf: a fixed colour per id
// for labels the legend lacks; unlabeled vertices: the vertex's RGB, else grey), or its RGB (grey
// without colour).
enum class VertexColoring { kLabel, kRgb };

struct VisualizationStyle {
  std::string frame_id = "map";
  std::string ns = "semfuse_map";  // the markers' namespace
  VertexColoring coloring = VertexColoring::kLabel;
  Stamp stamp;
};

// The RGB of vertex i of a block.
struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};
Rgb vertexColor(const MeshBlock& block, std::size_t i, const LabelLegend& legend, VertexColoring coloring);

// A block's triangles as an ADD TRIANGLE_LIST marker with identity pose and unit scale, three
// points and three colours per triangle; a DELETE marker for an empty block. `id` names the block
// within the namespace (the caller keeps one id per block).
void fillBlockMarker(visualization_msgs_msg_dds__Marker_& out, const MeshBlock& block, int32_t id, double voxel_size,
                     const LabelLegend& legend, const VisualizationStyle& style);
// DELETEALL in the namespace: what a cleared or replaced map becomes.
void fillDeleteAllMarker(visualization_msgs_msg_dds__Marker_& out, const VisualizationStyle& style);

// sensor_msgs/PointField datatypes (PointField.msg's constants).
namespace point_field {
inline constexpr uint8_t kUint32 = 6;
inline constexpr uint8_t kFloat32 = 7;
}  // namespace point_field

// Fields of the surface cloud: x, y, z FLOAT32 at 0, 4, 8; rgb FLOAT32 at 12 (0x00RRGGBB in the
// float's bits, as PCL packs it); label UINT32 at 16; confidence FLOAT32 at 20. 24 bytes a point.
inline constexpr uint32_t kSurfacePointStep = 24;
// One point per own vertex of every block (no vertex twice), height 1, little endian, dense.
void fillSurfaceCloud(sensor_msgs_msg_dds__PointCloud2_& out, const std::vector<const MeshBlock*>& blocks,
                      double voxel_size, const LabelLegend& legend, const VisualizationStyle& style);

}  // namespace semfuse::wire
