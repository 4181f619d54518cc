#pragma once
// One codec per service of idl/semfuse/srv.idl: the C++ request and reply
// (semfuse/core/service_types.hpp) <-> the generated Request_ / Response_ structs, both
// directions. The server's DDS adapter decodes requests and encodes replies, the client library
// encodes requests and decodes replies, and the fuzzers and tests use the same functions.
//
// Every codec has the same members, so that code can be written once for all services:
//   kName                 the service's name ("raycast"), as in its topics rq/semfuse/<name>Request
//   Request, Reply        the C++ types; a reply travels as ServiceReply<Reply> (code, message, value)
//   WireRequest, WireReply   the generated structs
//   encodeRequest(request, out), encodeReply(reply, out)
//       fill `out` with dds_alloc'd strings and sequences (those it held are freed first: pass a
//       zeroed struct or one Cyclone allocated, e.g. *dds::Sample). The rmw header
//       (client_guid_, sequence_number_) is left to the request/reply layer (dds/rpc.hpp).
//   decodeRequest(wire) -> Result<Request>
//       rejects what the C++ type cannot hold or a sequence that does not hold what it declares,
//       with a message naming the field; whether the request makes sense (a valid pose, a box
//       whose max is above its min, a limit) is the server's to check.
//   decodeReply(wire) -> Result<ServiceReply<Reply>>
//       the code and message always; the value is checked like any input. A reply that is not OK
//       is not refused for its value (the server's error says more): its value is then kept when
//       it decodes and left default when it does not.
#include <optional>
#include <vector>

#include <srv.h>

#include "semfuse/core/result.hpp"
#include "semfuse/core/server_status.hpp"
#include "semfuse/core/service_types.hpp"

namespace semfuse::wire {

struct RaycastCodec {
  static constexpr const char* kName = "raycast";
  using Request = RaycastRequest;
  using Reply = RaycastImages;
  using WireRequest = semfuse_srv_dds__Raycast_Request_;
  using WireReply = semfuse_srv_dds__Raycast_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  // Fails on an image side beyond what an int holds.
  static Result<Request> decodeRequest(const WireRequest& wire);
  // Layers travel as depth 32FC1, normals 32FC3, labels 16UC1, confidence 32FC1, color rgb8.
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  // Each layer must be empty or decode (image_message.hpp) to its type, CV_8UC3 RGB for colour.
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
  // decodeReply without copying the pixels: the images take over the sample's buffers
  // (takeImageMessage), so `wire` is left without them.
  static Result<ServiceReply<Reply>> takeReply(WireReply& wire);
};

struct LabelsAtCodec {
  static constexpr const char* kName = "labels_at";
  using Request = LabelsAtRequest;
  using Reply = std::vector<VoxelSample>;
  using WireRequest = semfuse_srv_dds__LabelsAt_Request_;
  using WireReply = semfuse_srv_dds__LabelsAt_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct RegionCodec {
  static constexpr const char* kName = "region";
  using Request = Box;
  using Reply = RegionSummary;
  using WireRequest = semfuse_srv_dds__Region_Request_;
  using WireReply = semfuse_srv_dds__Region_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct ObjectsCodec {
  static constexpr const char* kName = "objects";
  using Request = ObjectsRequest;
  using Reply = std::vector<ObjectInstance>;
  using WireRequest = semfuse_srv_dds__Objects_Request_;
  using WireReply = semfuse_srv_dds__Objects_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct MeshCodec {
  static constexpr const char* kName = "mesh";
  using Request = MeshRequest;
  using Reply = MeshChunk;
  using WireRequest = semfuse_srv_dds__Mesh_Request_;
  using WireReply = semfuse_srv_dds__Mesh_Response_;

  // No box travels as use_box false with zero corners; use_box false decodes to no box.
  static void encodeRequest(const Request& request, WireRequest& out);
  static Result<Request> decodeRequest(const WireRequest& wire);
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  // Whether the chunks add up to a mesh is the receiver's (client/src/mesh_assembly.hpp).
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

struct AdminCodec {
  static constexpr const char* kName = "admin";
  using Request = AdminRequest;
  using Reply = ServerStatus;
  using WireRequest = semfuse_srv_dds__Admin_Request_;
  using WireReply = semfuse_srv_dds__Admin_Response_;

  static void encodeRequest(const Request& request, WireRequest& out);
  // Fails on a command other than Admin_Request_Constants (0 stats, 1 save, 2 load, 3 reset).
  static Result<Request> decodeRequest(const WireRequest& wire);
  // The status goes out stamped with the time of the reply (status_codec.hpp).
  static void encodeReply(const ServiceReply<Reply>& reply, WireReply& out);
  static Result<ServiceReply<Reply>> decodeReply(const WireReply& wire);
};

}  // namespace semfuse::wire
