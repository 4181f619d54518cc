#include <cmath>
#include <string>

#include "semfuse/wire/distance_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void fillOccupancyGrid(nav_msgs_msg_dds__OccupancyGrid_& out, const OccupancyGrid& grid) {
  out.header.stamp.sec = grid.stamp.sec;
  out.header.stamp.nanosec = grid.stamp.nanosec;
  dds::setString(out.header.frame_id, grid.frame_id);
  out.info.map_load_time = out.header.stamp;
  out.info.resolution = static_cast<float>(grid.resolution);
  out.info.width = grid.width;
  out.info.height = grid.height;
  out.info.origin.position = {grid.origin.x(), grid.origin.y(), grid.z};
  out.info.origin.orientation = {0.0, 0.0, 0.0, 1.0};
  dds::setSequence(out.data, grid.cells.data(), grid.cells.size());
}

Result<OccupancyGrid> decodeOccupancyGrid(const nav_msgs_msg_dds__OccupancyGrid_& msg) {
  const auto& info = msg.info;
  if (info.width > (1u << 16) || info.height > (1u << 16))
    return makeError("occupancy grid of " + std::to_string(info.width) + "x" + std::to_string(info.height) +
                     " cells: sides above 65536");
  if (!(info.resolution > 0.0f) || !std::isfinite(info.resolution))
    return makeError("occupancy grid resolution must be a positive number, got " + std::to_string(info.resolution));
  const auto& q = info.origin.orientation;
  if (std::abs(q.x) > 1e-6 || std::abs(q.y) > 1e-6 || std::abs(q.z) > 1e-6 || std::abs(std::abs(q.w) - 1.0) > 1e-6)
    return makeError("occupancy grid with a rotated origin (semfuse grids are axis-aligned)");
  if (Status ok = validateSequence("occupancy grid data", msg.data._length, msg.data._maximum, msg.data._buffer); !ok)
    return makeError(ok.error());
  const uint64_t cells = uint64_t{info.width} * info.height;
  if (msg.data._length != cells)
    return makeError("occupancy grid data holds " + std::to_string(msg.data._length) + " cells, " +
                     std::to_string(info.width) + "x" + std::to_string(info.height) + " declared");
  OccupancyGrid grid;
  grid.frame_id = stringOf(msg.header.frame_id);
  grid.stamp = {msg.header.stamp.sec, msg.header.stamp.nanosec};
  grid.resolution = info.resolution;
  grid.width = info.width;
  grid.height = info.height;
  grid.origin = {info.origin.position.x, info.origin.position.y};
  grid.z = info.origin.position.z;
  grid.cells.assign(msg.data._buffer, msg.data._buffer + cells);
  for (std::size_t i = 0; i < grid.cells.size(); ++i)
    if (grid.cells[i] < -1 || grid.cells[i] > 100)
      return makeError("occupancy grid cell " + std::to_string(i) + " holds " + std::to_string(grid.cells[i]) +
                       " (0-100 or -1)");
  return grid;
}

void OccupancySliceCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.z_min = request.z_min;
  out.z_max = request.z_max;
  out.use_bounds = request.use_bounds;
  out.min_x = request.min.x();
  out.min_y = request.min.y();
  out.max_x = request.max.x();
  out.max_y = request.max.y();
  out.inflation_radius = request.inflation_radius;
}

Result<OccupancySliceRequest> OccupancySliceCodec::decodeRequest(const WireRequest& wire) {
  OccupancySliceRequest request;
  request.z_min = wire.z_min;
  request.z_max = wire.z_max;
  request.use_bounds = wire.use_bounds;
  request.min = {wire.min_x, wire.min_y};
  request.max = {wire.max_x, wire.max_y};
  request.inflation_radius = wire.inflation_radius;
  return request;
}

void OccupancySliceCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  fillOccupancyGrid(out.grid, reply.value);
}

Result<ServiceReply<OccupancyGrid>> OccupancySliceCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] { return decodeOccupancyGrid(wire.grid); });
}

}  // namespace semfuse::wire
