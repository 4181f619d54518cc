#pragma once
// Codecs of the distance field's services (distance, occupancy_slice, semantic_distance,
// semantic_slice, segment_check; idl/semfuse/srv.idl), with the members every service codec has
// (service_codecs.hpp says what each does), and the nav_msgs/OccupancyGrid message that the
// occupancy_slice reply and the rt/semfuse/occupancy topic carry.
#include <vector>

#include <nav_msgs.h>
#include <srv.h>

#include "semfuse/core/distance_service_types.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/service_types.hpp"

namespace semfuse::wire {

// nav_msgs/OccupancyGrid: header (stamp, frame_id), info (resolution, width, height, origin
// pose at (origin.x, origin.y, z) with identity orientation), data row-major. fill writes
// dds_alloc'd buffers into `out` (freed with the sample).
void fillOccupancyGrid(nav_msgs_msg_dds__OccupancyGrid_& out, const OccupancyGrid& grid);
// Refuses a grid whose data does not hold width * height cells, sides beyond 65536, a resolution
// that is not a positive number, a rotated origin (semfuse writes none) or cell values outside
// -1..100.
Result<OccupancyGrid> decodeOccupancyGrid(const nav_msgs_msg_dds__OccupancyGrid_& msg);

struct DistanceCodec {
  static constexpr const char* kName = "distance";
  using Request = DistanceRequest;
  using Reply = std::vector<DistanceSample>;
  using WireRequest = semfuse_srv_dds__Distance_Request_;
  using WireReply = semfuse_srv_dds__Distance_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct OccupancySliceCodec {
  static constexpr const char* kName = "occupancy_slice";
  using Request = OccupancySliceRequest;
  using Reply = OccupancyGrid;
  using WireRequest = semfuse_srv_dds__OccupancySlice_Request_;
  using WireReply = semfuse_srv_dds__OccupancySlice_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct SemanticDistanceCodec {
  static constexpr const char* kName = "semantic_distance";
  using Request = SemanticDistanceRequest;
  using Reply = std::vector<SemanticSample>;
  using WireRequest = semfuse_srv_dds__SemanticDistance_Request_;
  using WireReply = semfuse_srv_dds__SemanticDistance_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct SemanticSliceCodec {
  static constexpr const char* kName = "semantic_slice";
  using Request = SemanticSliceRequest;
  using Reply = SemanticSlice;
  using WireRequest = semfuse_srv_dds__SemanticSlice_Request_;
  using WireReply = semfuse_srv_dds__SemanticSlice_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  // The distances travel as a 32FC1 image.
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct SegmentCheckCodec {
  static constexpr const char* kName = "segment_check";
  using Request = SegmentCheckRequest;
  using Reply = std::vector<SegmentResult>;
  using WireRequest = semfuse_srv_dds__SegmentCheck_Request_;
  using WireReply = semfuse_srv_dds__SegmentCheck_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  // Fails on a status other than SegmentResult_Constants (0 free, 1 collision, 2 unknown).
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

}  // namespace semfuse::wire
