// MapClient's calls to the distance field's services (distance, occupancy_slice,
// semantic_distance, semantic_slice, segment_check).
#include "rpc_call.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/dds/topics.hpp"
#include "semfuse/wire/distance_codecs.hpp"

namespace semfuse::client {

struct MapClient::DistanceRpcs {
  explicit DistanceRpcs(const dds::Participant& p)
      : distance(p, dds::topics::distance()),
        occupancy_slice(p, dds::topics::occupancySlice()),
        semantic_distance(p, dds::topics::semanticDistance()),
        semantic_slice(p, dds::topics::semanticSlice()),
        segment_check(p, dds::topics::segmentCheck()) {}

  Rpc<wire::DistanceCodec> distance;
  Rpc<wire::OccupancySliceCodec> occupancy_slice;
  Rpc<wire::SemanticDistanceCodec> semantic_distance;
  Rpc<wire::SemanticSliceCodec> semantic_slice;
  Rpc<wire::SegmentCheckCodec> segment_check;
};

void MapClient::DistanceRpcsDeleter::operator()(DistanceRpcs* rpcs) const { delete rpcs; }

std::unique_ptr<MapClient::DistanceRpcs, MapClient::DistanceRpcsDeleter> MapClient::makeDistanceRpcs(
    const dds::Participant& participant) {
  return std::unique_ptr<DistanceRpcs, DistanceRpcsDeleter>(new DistanceRpcs(participant));
}

CallResult<std::vector<DistanceSample>> MapClient::distances(const std::vector<Eigen::Vector3d>& points,
                                                             Timeout timeout) {
  return call<wire::DistanceCodec>(distance_->distance, {points}, timeout);
}

CallResult<OccupancyGrid> MapClient::occupancySlice(const OccupancySliceRequest& request, Timeout timeout) {
  return call<wire::OccupancySliceCodec>(distance_->occupancy_slice, request, timeout);
}

CallResult<std::vector<SemanticSample>> MapClient::semanticDistances(const std::vector<LabelId>& labels,
                                                                     const std::vector<Eigen::Vector3d>& points,
                                                                     Timeout timeout) {
  return call<wire::SemanticDistanceCodec>(distance_->semantic_distance, {labels, points}, timeout);
}

CallResult<SemanticSlice> MapClient::semanticSlice(const SemanticSliceRequest& request, Timeout timeout) {
  return call<wire::SemanticSliceCodec>(distance_->semantic_slice, request, timeout);
}

CallResult<std::vector<SegmentResult>> MapClient::checkSegments(const std::vector<Segment>& segments, double radius,
                                                                Timeout timeout) {
  return call<wire::SegmentCheckCodec>(distance_->segment_check, {segments, radius}, timeout);
}

}  // namespace semfuse::client
