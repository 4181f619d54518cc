#include "semfuse/wire/ros_visualization.hpp"

#include <cstring>

#include "semfuse/dds/sample.hpp"

namespace semfuse::wire {
namespace {

constexpr uint8_t kGrey = 170;

void fillHeader(std_msgs_msg_dds__Header_& header, const VisualizationStyle& style) {
  header.stamp.sec = style.stamp.sec;
  header.stamp.nanosec = style.stamp.nanosec;
  dds::setString(header.frame_id, style.frame_id);
}

// Fields every marker of ours shares: namespace, identity pose, unit scale, opaque white, forever.
void fillCommon(visualization_msgs_msg_dds__Marker_& out, const VisualizationStyle& style) {
  fillHeader(out.header, style);
  dds::setString(out.ns, style.ns);
  out.type = visualization_msgs_msg_dds__Marker_Constants_TRIANGLE_LIST;
  out.pose.position = {0.0, 0.0, 0.0};
  out.pose.orientation = {0.0, 0.0, 0.0, 1.0};
  out.scale = {1.0, 1.0, 1.0};
  out.color = {1.0F, 1.0F, 1.0F, 1.0F};
  out.lifetime = {0, 0};
  out.frame_locked = false;
  // Strings a ROS 2 message always carries (empty, not null).
  dds::setString(out.texture_resource, "");
  dds::setString(out.texture.header.frame_id, "");
  dds::setString(out.texture.format, "");
  dds::setString(out.text, "");
  dds::setString(out.mesh_resource, "");
  dds::setString(out.mesh_file.filename, "");
}

void addField(sensor_msgs_msg_dds__PointField_& field, const char* name, uint32_t offset, uint8_t datatype) {
  dds::setString(field.name, name);
  field.offset = offset;
  field.datatype = datatype;
  field.count = 1;
}

}  // namespace

Rgb vertexColor(const MeshBlock& block, std::size_t i, const LabelLegend& legend, VertexColoring coloring) {
  const LabelId label = block.labels[i];
  if (coloring == VertexColoring::kLabel && label != kUnlabeled) {
    const auto rgb = legend.colorOf(label);
    return {rgb[0], rgb[1], rgb[2]};
  }
  if (block.colors.empty()) return {kGrey, kGrey, kGrey};
  return {block.colors[3 * i], block.colors[3 * i + 1], block.colors[3 * i + 2]};
}

void fillBlockMarker(visualization_msgs_msg_dds__Marker_& out, const MeshBlock& block, int32_t id, double voxel_size,
                     const LabelLegend& legend, const VisualizationStyle& style) {
  fillCommon(out, style);
  out.id = id;
  if (block.empty()) {
    out.action = visualization_msgs_msg_dds__Marker_Constants_DELETE;
    return;
  }
  out.action = visualization_msgs_msg_dds__Marker_Constants_ADD;
  const std::size_t corners = block.triangles.size();
  dds::resizeSequence(out.points, corners);
  dds::resizeSequence(out.colors, corners);
  for (std::size_t c = 0; c < corners; ++c) {
    const std::size_t v = block.triangles[c];
    const Eigen::Vector3f p = block.position(v, voxel_size);
    out.points._buffer[c] = {p.x(), p.y(), p.z()};
    const Rgb rgb = vertexColor(block, v, legend, style.coloring);
    out.colors._buffer[c] = {rgb.r / 255.0F, rgb.g / 255.0F, rgb.b / 255.0F, 1.0F};
  }
}

void fillDeleteAllMarker(visualization_msgs_msg_dds__Marker_& out, const VisualizationStyle& style) {
  fillCommon(out, style);
  out.id = 0;
  out.action = visualization_msgs_msg_dds__Marker_Constants_DELETEALL;
}

void fillSurfaceCloud(sensor_msgs_msg_dds__PointCloud2_& out, const std::vector<const MeshBlock*>& blocks,
                      double voxel_size, const LabelLegend& legend, const VisualizationStyle& style) {
  fillHeader(out.header, style);
  std::size_t points = 0;
  for (const MeshBlock* block : blocks) points += block->own_vertices;
  dds::resizeSequence(out.fields, 6);
  addField(out.fields._buffer[0], "x", 0, point_field::kFloat32);
  addField(out.fields._buffer[1], "y", 4, point_field::kFloat32);
  addField(out.fields._buffer[2], "z", 8, point_field::kFloat32);
  addField(out.fields._buffer[3], "rgb", 12, point_field::kFloat32);
  addField(out.fields._buffer[4], "label", 16, point_field::kUint32);
  addField(out.fields._buffer[5], "confidence", 20, point_field::kFloat32);
  out.height = 1;
  out.width = static_cast<uint32_t>(points);
  out.is_bigendian = false;
  out.point_step = kSurfacePointStep;
  out.row_step = static_cast<uint32_t>(points * kSurfacePointStep);
  out.is_dense = true;
  dds::resizeSequence(out.data, points * kSurfacePointStep);
  uint8_t* at = out.data._buffer;
  for (const MeshBlock* block : blocks)
    for (std::size_t v = 0; v < block->own_vertices; ++v, at += kSurfacePointStep) {
      const Eigen::Vector3f p = block->position(v, voxel_size);
      const Rgb rgb = vertexColor(*block, v, legend, style.coloring);
      const uint32_t packed = (uint32_t{rgb.r} << 16) | (uint32_t{rgb.g} << 8) | uint32_t{rgb.b};
      const uint32_t label = block->labels[v];
      const float confidence = block->scores[v];
      std::memcpy(at, p.data(), 12);  // little-endian hosts only, as the rest of the wire code
      std::memcpy(at + 12, &packed, 4);
      std::memcpy(at + 16, &label, 4);
      std::memcpy(at + 20, &confidence, 4);
    }
}

}  // namespace semfuse::wire
