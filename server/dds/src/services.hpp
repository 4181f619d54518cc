#pragma once
// The DDS adapter of the query services (raycast, labels_at, region, objects, mesh, admin,
// map_blocks, and the distance field's distance, occupancy_slice, semantic_distance, semantic_slice,
// segment_check): one dds::RpcServer thread per service that decodes each request with its codec
// (common/wire/service_codecs.hpp, map_update_codecs.hpp, distance_codecs.hpp), calls the
// service's handler (service_handlers.hpp: no DDS),
// encodes the reply and writes it. Every request gets a reply: one that does not decode gets
// INVALID_ARGUMENT and the decoder's message. Refused queries are counted in the server's
// status (invalid_query), with their messages; a failed admin command is recorded as an error of
// the admin service. Queries read under the Mapper's shared lock; admin load/reset run on the
// fusion thread, the only writer.
#include <functional>
#include <memory>
#include <string>
#include <utility>

#include "distance_field.hpp"
#include "distance_handlers.hpp"
#include "fusion_loop.hpp"
#include "held_meshes.hpp"
#include "map_blocks_handler.hpp"
#include "map_updater.hpp"
#include "mapper.hpp"
#include "mapper_access.hpp"
#include "objects_refresher.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/topic.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/dds/writer.hpp"
#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/map_update_codecs.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "server_config.hpp"
#include "server_state.hpp"
#include "service_handlers.hpp"

namespace semfuse::server {

class Services {
 public:
  using SnapshotFn = std::function<ServerStatus()>;
  using SaveFn = std::function<Status(const std::string& path)>;

  // `field` is the distance field (null without --esdf: its services answer UNAVAILABLE);
  // `map_updates` the live mesh, whose store map_blocks pages (null: map_blocks answers UNAVAILABLE).
  Services(const dds::Participant& participant, const ServerConfig& config, Mapper& mapper, FusionLoop& fusion,
           ServerState& state, SnapshotFn snapshot, SaveFn save, const DistanceField* field = nullptr,
           MapUpdater* map_updates = nullptr);
  ~Services();

  // A frame the fusion thread integrated, with the pose it was fused at: the objects' "frames
  // that saw it" (objects::ViewIndex). From the fusion thread.
  void recordView(const Frame& frame, const Pose& camera_to_world);

 private:
  template <class Codec>
  using Server = std::unique_ptr<dds::RpcServer<typename Codec::WireRequest, typename Codec::WireReply>>;

  // Serves one service: decode, `handle`, encode. A request that does not decode is counted in
  // the status as an invalid query, and so are the handler's refusals with count_refusals.
  template <class Codec, class Handle>
  Server<Codec> serve(const dds::Participant& participant, const dds::topics::ServiceTopics& topics, Handle handle,
                      bool count_refusals = true);

  ServerState& state_;
  MapperAccess map_;
  QueryLimits limits_;
  HeldMeshes meshes_;
  // Where the objects' changes are published (null when DDS Security's permissions leave the
  // topic out: then they go to the log only); before the tracker that writes them.
  std::unique_ptr<dds::Topic<semfuse_msg_dds__ObjectEvents_>> object_events_topic_;
  std::unique_ptr<dds::Writer<semfuse_msg_dds__ObjectEvents_>> object_events_writer_;
  // The map's objects, shared by the objects and mesh services so that ids stay with objects.
  std::unique_ptr<objects::ObjectTracker> objects_;
  std::unique_ptr<ObjectsRefresher> objects_refresher_;  // after the tracker: stops before it goes
  std::pair<float, float> view_depth_range_;             // the map's min and max depth: what a frame saw
  AdminActions admin_;
  DistanceQueryContext distance_;
  // Last, so that their threads stop before what the handlers use goes.
  Server<wire::RaycastCodec> raycast_server_;
  Server<wire::LabelsAtCodec> labels_at_server_;
  Server<wire::RegionCodec> region_server_;
  Server<wire::ObjectsCodec> objects_server_;
  Server<wire::MeshCodec> mesh_server_;
  Server<wire::AdminCodec> admin_server_;
  Server<wire::MapBlocksCodec> map_blocks_server_;
  Server<wire::DistanceCodec> distance_server_;
  Server<wire::OccupancySliceCodec> occupancy_slice_server_;
  Server<wire::SemanticDistanceCodec> semantic_distance_server_;
  Server<wire::SemanticSliceCodec> semantic_slice_server_;
  Server<wire::SegmentCheckCodec> segment_check_server_;
};

}  // namespace semfuse::server
