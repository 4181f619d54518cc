#include "services.hpp"

#include <chrono>
#include <utility>

#include <spdlog/spdlog.h>

#include "semfuse/dds/error.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "tbb_worker_names.hpp"
#include "thread_priority.hpp"

namespace semfuse::server {

template <class Codec, class Handle>
Services::Server<Codec> Services::serve(const dds::Participant& participant, const dds::topics::ServiceTopics& topics,
                                        Handle handle, bool count_refusals) {
  using WireRequest = typename Codec::WireRequest;
  using WireReply = typename Codec::WireReply;
  auto on_request = [this, handle = std::move(handle), count_refusals](const WireRequest& wire_request,
                                                                       WireReply& wire_reply) {
    // The TBB workers that help this service's thread are named first (tbb_worker_names.hpp).
    nameTbbWorkers();
    lowerToQueryPriority();  // frames first (thread_priority.hpp)
    auto request = Codec::decodeRequest(wire_request);
    ServiceReply<typename Codec::Reply> reply =
        request ? handle(request.value())
                : ServiceReply<typename Codec::Reply>::failure(ReplyCode::kInvalidArgument, request.error());
    // A query the server refused (the client's mistake, or a failure to answer it) is counted;
    // a mesh that is no longer held is not a mistake. Admin commands record their own failures.
    const bool refused =
        !request || (count_refusals && (reply.code == ReplyCode::kInvalidArgument ||
                                        reply.code == ReplyCode::kTooLarge || reply.code == ReplyCode::kInternal));
    if (refused) {
      state_.reject(reason::kInvalidQuery, "", std::string("query ") + Codec::kName, reply.message);
    }
    Codec::encodeReply(reply, wire_reply);
  };
  return std::make_unique<dds::RpcServer<WireRequest, WireReply>>(participant, topics, std::move(on_request));
}

Services::Services(const dds::Participant& participant, const ServerConfig& config, Mapper& mapper, FusionLoop& fusion,
                   ServerState& state, SnapshotFn snapshot, SaveFn save, const DistanceField* field,
                   MapUpdater* map_updates)
    : state_(state), map_(mapper) {
  using namespace std::chrono_literals;
  limits_ = config.queries;
  // Up from the map's floor where it has one (a map in a camera's frame has y down), else z.
  objects::ObjectParams object_params;
  object_params.up_from_floor = true;
  objects_ = makeObjectTracker(mapper.legend(), config.volume.voxel_size, object_params);
  view_depth_range_ = {config.volume.min_depth, config.volume.max_depth};
  try {
    object_events_topic_ =
        std::make_unique<dds::Topic<semfuse_msg_dds__ObjectEvents_>>(participant, dds::topics::kObjectEvents);
    object_events_writer_ =
        std::make_unique<dds::Writer<semfuse_msg_dds__ObjectEvents_>>(*object_events_topic_, dds::qos::objectEvents());
  } catch (const dds::DdsError& e) {
    // E.g. DDS Security permissions written before this topic: the objects are served without it.
    spdlog::error("object events off: {}", e.what());
    state_.errors.record("object_events", e.what());
  }
  // On the thread that regrouped the objects (a query of objects or of an object's mesh, sf-objects).
  objects_->setListener([this](const ObjectEvents& update) {
    std::size_t counts[4] = {0, 0, 0, 0};
    for (const ObjectEvent& event : update.events) ++counts[static_cast<int>(event.kind)];
    spdlog::info("objects update {}: {} objects; {} appeared, {} merged, {} split, {} vanished", update.update,
                 update.object_count, counts[0], counts[1], counts[2], counts[3]);
    if (!object_events_writer_) return;
    const wire::EncodedObjectEvents encoded = wire::encodeObjectEvents(update);
    if (Status ok = object_events_writer_->write(encoded.msg()); !ok) spdlog::warn("object events: {}", ok.error());
  });
  admin_.map_file = config.map_file;
  admin_.save = std::move(save);
  // The frames that saw the old map's objects go with it, on the fusion thread, between two frames.
  admin_.load = [this, &mapper, &fusion](const std::string& path) {
    return fusion.runOnFusionThread(
        [this, &mapper, path] {
          Status loaded = mapper.load(path);
          if (loaded) objects_->forgetViews();
          return loaded;
        },
        60s);
  };
  admin_.reset = [this, &mapper, &fusion] {
    return fusion.runOnFusionThread(
        [this, &mapper] {
          mapper.reset();
          objects_->forgetViews();
          return Status::Ok();
        },
        60s);
  };
  // A failed admin command is an error of the admin service's, in the status's last errors.
  admin_.failed = [this](const Error& error) {
    state_.errors.record("admin", error.message);
    state_.touch();
  };
  admin_.status = std::move(snapshot);

  namespace topics = dds::topics;
  raycast_server_ = serve<wire::RaycastCodec>(participant, topics::raycast(), [this](const RaycastRequest& request) {
    return handleRaycast(request, map_, limits_);
  });
  labels_at_server_ = serve<wire::LabelsAtCodec>(
      participant, topics::labelsAt(),
      [this](const LabelsAtRequest& request) { return handleLabelsAt(request, map_, limits_); });
  region_server_ = serve<wire::RegionCodec>(participant, topics::region(),
                                            [this](const Box& box) { return handleRegion(box, map_); });
  objects_refresher_ = std::make_unique<ObjectsRefresher>(map_, *objects_, config.objects_rate_hz, [this] {
    return object_events_writer_ && object_events_writer_->matchedReaders() > 0;
  });
  objects_server_ = serve<wire::ObjectsCodec>(participant, topics::objects(), [this](const ObjectsRequest& request) {
    objects_refresher_->touch();
    return handleObjects(request, map_, *objects_);
  });
  mesh_server_ = serve<wire::MeshCodec>(participant, topics::mesh(), [this](const MeshRequest& request) {
    return handleMesh(request, map_, meshes_, limits_, objects_.get());
  });
  admin_server_ = serve<wire::AdminCodec>(
      participant, topics::admin(), [this](const AdminRequest& request) { return handleAdmin(request, admin_); },
      /*count_refusals=*/false);
  const uint32_t page_bytes = config.map_updates.page_bytes;
  map_blocks_server_ = serve<wire::MapBlocksCodec>(
      participant, topics::mapBlocks(), [map_updates, page_bytes](const MapBlocksRequest& request) {
        if (map_updates) map_updates->touch();  // someone follows the mesh: keep it up to date
        return handleMapBlocks(request, map_updates ? &map_updates->store() : nullptr, page_bytes);
      });

  distance_ = {field, &mapper.legend(), limits_, config.esdf.max_slice_cells, config.esdf.occupancy_frame_id};
  distance_server_ = serve<wire::DistanceCodec>(
      participant, topics::distance(), [this](const DistanceRequest& r) { return handleDistance(r, distance_); });
  occupancy_slice_server_ = serve<wire::OccupancySliceCodec>(
      participant, topics::occupancySlice(),
      [this](const OccupancySliceRequest& r) { return handleOccupancySlice(r, distance_); });
  semantic_distance_server_ = serve<wire::SemanticDistanceCodec>(
      participant, topics::semanticDistance(),
      [this](const SemanticDistanceRequest& r) { return handleSemanticDistance(r, distance_); });
  semantic_slice_server_ = serve<wire::SemanticSliceCodec>(
      participant, topics::semanticSlice(),
      [this](const SemanticSliceRequest& r) { return handleSemanticSlice(r, distance_); });
  segment_check_server_ =
      serve<wire::SegmentCheckCodec>(participant, topics::segmentCheck(),
                                     [this](const SegmentCheckRequest& r) { return handleSegmentCheck(r, distance_); });
}

void Services::recordView(const Frame& frame, const Pose& camera_to_world) {
  objects_->recordView(frame, camera_to_world, view_depth_range_.first, view_depth_range_.second);
}

Services::~Services() = default;

}  // namespace semfuse::server
