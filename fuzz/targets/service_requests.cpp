// Fuzz target: the query services' requests. First byte picks the service (0 raycast,
// 1 labels_at, 2 region, 3 objects, 4 mesh; 5 distance, 6 occupancy_slice, 7 semantic_distance,
// 8 semantic_slice, 9 segment_check), the rest is its request's CDR as the RpcServer receives it. The request then goes
// the server's way, minus DDS: the service's codec decodes it (common/wire/service_codecs.hpp), the server's own
// handler answers it (server/core/src/service_handlers.cpp, distance_handlers.cpp) on a small labeled map and its
// distance field, and the codec encodes the reply.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "distance_handlers.hpp"
#include "fuzz_support.hpp"
#include "map_access.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "service_handlers.hpp"
#include "tiny_map.hpp"

namespace {
using namespace semfuse;

const server::MapAccess& tinyMap() {
  static const server::VolumeAccess map(std::make_shared<const volume::LabeledVolume>(fuzz::makeTinyMap()),
                                        *builtinLegend("voc"));
  return map;
}

// The tiny map's distance field (the TSDF's band: the map has no observed free space).
const server::DistanceQueryContext& tinyField() {
  static const server::FixedDistanceField source([] {
    const volume::LabeledVolume map = fuzz::makeTinyMap();
    auto field = std::make_shared<esdf::EsdfMap>(map.voxelSize());
    field->apply(esdf::copyChanges(map, 0));
    return std::shared_ptr<const esdf::EsdfMap>(std::move(field));
  }());
  static const server::DistanceQueryContext context = [] {
    server::DistanceQueryContext c;
    c.field = &source;
    c.legend = &tinyMap().legend();
    c.limits.max_points = 4096;
    c.max_slice_cells = 256 * 256;
    return c;
  }();
  return context;
}

// The server serves up to --max-raycast-pixels (default 2048^2); a smaller bound keeps every
// input fast without changing which code runs.
server::QueryLimits limits() {
  server::QueryLimits limits;
  limits.max_raycast_pixels = 64 * 64;
  limits.mesh_chunk_bytes = 1024;
  return limits;
}

// CDR -> request -> handler -> reply on the wire. Returns the reply for the service's own checks
// (null when the bytes are no request of this service).
template <class Codec, class Handle>
std::unique_ptr<ServiceReply<typename Codec::Reply>> serve(const uint8_t* data, size_t size, Handle handle) {
  auto sample = dds::deserialize<typename Codec::WireRequest>(data, size);
  if (!sample) return nullptr;
  auto request = Codec::decodeRequest(*sample.value());
  if (!request) return nullptr;
  auto reply = std::make_unique<ServiceReply<typename Codec::Reply>>(handle(request.value()));
  SEMFUSE_FUZZ_CHECK(reply->ok() || !reply->message.empty());
  dds::Sample<typename Codec::WireReply> wire_reply;
  Codec::encodeReply(*reply, *wire_reply);
  SEMFUSE_FUZZ_CHECK(wire_reply->status == static_cast<int32_t>(reply->code));
  return reply;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int service = data[0] % 10;
  ++data;
  --size;
  const server::QueryLimits bounds = limits();
  switch (service) {
    case 0: {
      RaycastRequest asked;
      auto reply = serve<wire::RaycastCodec>(data, size, [&](const RaycastRequest& request) {
        asked = request;
        return server::handleRaycast(request, tinyMap(), bounds);
      });
      // What passed the checks renders every requested layer at the requested size.
      if (reply && reply->ok() && (asked.layers & kDepthLayer)) {
        SEMFUSE_FUZZ_CHECK(reply->value.depth.cols == asked.intrinsics.width &&
                           reply->value.depth.rows == asked.intrinsics.height);
      }
      break;
    }
    case 1: {
      size_t points = 0;
      auto reply = serve<wire::LabelsAtCodec>(data, size, [&](const LabelsAtRequest& request) {
        points = request.points.size();
        return server::handleLabelsAt(request, tinyMap(), bounds);
      });
      if (reply && reply->ok()) SEMFUSE_FUZZ_CHECK(reply->value.size() == points);
      break;
    }
    case 2: {
      auto reply =
          serve<wire::RegionCodec>(data, size, [](const Box& box) { return server::handleRegion(box, tinyMap()); });
      if (reply && reply->ok()) {
        SEMFUSE_FUZZ_CHECK(reply->value.occupied_voxels + reply->value.free_voxels == reply->value.observed_voxels);
      }
      break;
    }
    case 3:
      (void)serve<wire::ObjectsCodec>(
          data, size, [](const ObjectsRequest& request) { return server::handleObjects(request, tinyMap()); });
      break;
    case 5: {
      size_t points = 0;
      auto reply = serve<wire::DistanceCodec>(data, size, [&](const DistanceRequest& request) {
        points = request.points.size();
        return server::handleDistance(request, tinyField());
      });
      if (reply && reply->ok()) SEMFUSE_FUZZ_CHECK(reply->value.size() == points);
      break;
    }
    case 6: {
      auto reply = serve<wire::OccupancySliceCodec>(data, size, [](const OccupancySliceRequest& request) {
        return server::handleOccupancySlice(request, tinyField());
      });
      if (reply && reply->ok())
        SEMFUSE_FUZZ_CHECK(reply->value.cells.size() == uint64_t{reply->value.width} * reply->value.height);
      break;
    }
    case 7: {
      size_t points = 0;
      auto reply = serve<wire::SemanticDistanceCodec>(data, size, [&](const SemanticDistanceRequest& request) {
        points = request.points.size();
        return server::handleSemanticDistance(request, tinyField());
      });
      if (reply && reply->ok()) SEMFUSE_FUZZ_CHECK(reply->value.size() == points);
      break;
    }
    case 8: {
      auto reply = serve<wire::SemanticSliceCodec>(data, size, [](const SemanticSliceRequest& request) {
        return server::handleSemanticSlice(request, tinyField());
      });
      if (reply && reply->ok()) SEMFUSE_FUZZ_CHECK(reply->value.distance.type() == CV_32FC1);
      break;
    }
    case 9: {
      size_t segments = 0;
      auto reply = serve<wire::SegmentCheckCodec>(data, size, [&](const SegmentCheckRequest& request) {
        segments = request.segments.size();
        return server::handleSegmentCheck(request, tinyField());
      });
      if (reply && reply->ok()) SEMFUSE_FUZZ_CHECK(reply->value.size() == segments);
      break;
    }
    case 4:
    default: {
      // Each input gets its own held meshes, so that one input's mesh cannot answer another's.
      server::HeldMeshes meshes;
      auto reply = serve<wire::MeshCodec>(data, size, [&](const MeshRequest& request) {
        return server::handleMesh(request, tinyMap(), meshes, bounds);
      });
      if (reply && reply->ok()) {
        SEMFUSE_FUZZ_CHECK(reply->value.chunk_index < reply->value.chunk_count);
        SEMFUSE_FUZZ_CHECK(reply->value.ply.size() <= reply->value.total_bytes);
      }
      break;
    }
  }
  return 0;
}
