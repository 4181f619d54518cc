#pragma once
// The distance field's services (distance, occupancy_slice, semantic_distance, semantic_slice,
// segment_check) as plain functions, as service_handlers.hpp has the others: the decoded request
// and the field in, the reply out, no DDS. `field` is null when the server runs without --esdf:
// every request then gets UNAVAILABLE saying so. Bad requests (non-finite numbers, more points
// than --max-points, an empty or out-of-legend label set, an inverted height band, a slice of no
// area or beyond --esdf.max-slice-cells) get INVALID_ARGUMENT or TOO_LARGE and a message.
#include <vector>

#include "distance_source.hpp"
#include "esdf_config.hpp"
#include "query_limits.hpp"
#include "semfuse/core/distance_service_types.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/service_types.hpp"

namespace semfuse::server {

// What the handlers need besides the request.
struct DistanceQueryContext {
  const DistanceSource* field = nullptr;  // null: no distance field (--esdf off)
  const LabelLegend* legend = nullptr;
  QueryLimits limits;
  uint64_t max_slice_cells = uint64_t{4096} * 4096;
  std::string frame_id = "map";
};

ServiceReply<std::vector<DistanceSample>> handleDistance(const DistanceRequest& request,
                                                         const DistanceQueryContext& context);
ServiceReply<OccupancyGrid> handleOccupancySlice(const OccupancySliceRequest& request,
                                                 const DistanceQueryContext& context);
ServiceReply<std::vector<SemanticSample>> handleSemanticDistance(const SemanticDistanceRequest& request,
                                                                 const DistanceQueryContext& context);
ServiceReply<SemanticSlice> handleSemanticSlice(const SemanticSliceRequest& request,
                                                const DistanceQueryContext& context);
ServiceReply<std::vector<SegmentResult>> handleSegmentCheck(const SegmentCheckRequest& request,
                                                            const DistanceQueryContext& context);

// The occupancy grid the server publishes: the band of `config` over the whole observed extent.
OccupancyGrid publishedOccupancyGrid(const DistanceSource& field, const EsdfConfig& config);

}  // namespace semfuse::server
