#include "distance_handlers.hpp"

#include <cmath>
#include <string>

#include "semfuse/esdf/distance_queries.hpp"

namespace semfuse::server {

// One set of cell values: nav_msgs/OccupancyGrid's, as the wire and the library write them.
static_assert(kOccupancyFree == esdf::kCellFree && kOccupancyInflated == esdf::kCellInflated &&
              kOccupancyOccupied == esdf::kCellOccupied && kOccupancyUnknown == esdf::kCellUnknown);

namespace {

template <class T>
ServiceReply<T> refuse(ReplyCode code, std::string message) {
  return ServiceReply<T>::failure(code, std::move(message));
}

constexpr const char* kNoField = "the server keeps no distance field: start it with --esdf";

bool finite(double v) { return std::isfinite(v); }

// Points: within the limit, every coordinate finite.
Status checkPoints(const std::vector<Eigen::Vector3d>& points, const QueryLimits& limits, ReplyCode& code) {
  code = ReplyCode::kInvalidArgument;
  if (points.empty()) return makeError("no points");
  if (points.size() > limits.max_points) {
    code = ReplyCode::kTooLarge;
    return makeError(std::to_string(points.size()) + " points exceed the limit of " +
                     std::to_string(limits.max_points));
  }
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!points[i].allFinite()) return makeError("point " + std::to_string(i) + " is not finite");
  return Status::Ok();
}

Status checkLabels(const std::vector<LabelId>& labels, const LabelLegend* legend) {
  if (labels.empty()) return makeError("no labels: name at least one label id");
  for (LabelId label : labels) {
    if (label == kUnlabeled) return makeError("label 0 (unlabeled) has no surface");
    if (legend && !legend->contains(label))
      return makeError("label " + std::to_string(label) + " is not in the legend '" + legend->name + "'");
  }
  return Status::Ok();
}

Status checkArea(const Eigen::Vector2d& min, const Eigen::Vector2d& max, const char* what) {
  if (!min.allFinite() || !max.allFinite()) return makeError(std::string(what) + " corners must be finite");
  if (!(max.x() > min.x()) || !(max.y() > min.y()))
    return makeError(std::string(what) + " has no area: max must be above min in x and y");
  return Status::Ok();
}

DistanceSample toSample(const esdf::DistanceSample& s) { return {s.known, s.beyond, s.distance, s.gradient}; }

}  // namespace

ServiceReply<std::vector<DistanceSample>> handleDistance(const DistanceRequest& request,
                                                         const DistanceQueryContext& context) {
  using Reply = std::vector<DistanceSample>;
  if (!context.field) return refuse<Reply>(ReplyCode::kUnavailable, kNoField);
  ReplyCode code;
  if (Status ok = checkPoints(request.points, context.limits, code); !ok) return refuse<Reply>(code, ok.error());
  ServiceReply<Reply> reply;
  std::vector<esdf::DistanceSample> samples;
  context.field->read([&](const esdf::EsdfMap& field) { samples = esdf::distancesAt(field, request.points); });
  reply.value.reserve(samples.size());
  for (const auto& s : samples) reply.value.push_back(toSample(s));
  return reply;
}

ServiceReply<OccupancyGrid> handleOccupancySlice(const OccupancySliceRequest& request,
                                                 const DistanceQueryContext& context) {
  using Reply = OccupancyGrid;
  if (!context.field) return refuse<Reply>(ReplyCode::kUnavailable, kNoField);
  if (!finite(request.z_min) || !finite(request.z_max) || !finite(request.inflation_radius))
    return refuse<Reply>(ReplyCode::kInvalidArgument, "z_min, z_max and inflation_radius must be finite");
  if (request.z_max < request.z_min)
    return refuse<Reply>(ReplyCode::kInvalidArgument, "the height band is inverted: z_max " +
                                                          std::to_string(request.z_max) + " is below z_min " +
                                                          std::to_string(request.z_min));
  if (request.inflation_radius < 0.0)
    return refuse<Reply>(ReplyCode::kInvalidArgument, "inflation_radius must be >= 0");
  if (request.use_bounds)
    if (Status ok = checkArea(request.min, request.max, "the slice's box"); !ok)
      return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  esdf::OccupancyRequest slice;
  slice.z_min = request.z_min;
  slice.z_max = request.z_max;
  slice.inflation_radius = request.inflation_radius;
  if (request.use_bounds) slice.bounds = esdf::SliceBounds{request.min, request.max};
  ServiceReply<Reply> reply;
  context.field->read([&](const esdf::EsdfMap& field) {
    const uint64_t cells = esdf::occupancyCellCount(field, slice);
    if (cells > context.max_slice_cells) {
      reply = refuse<Reply>(ReplyCode::kTooLarge, std::to_string(cells) + " cells exceed the limit of " +
                                                      std::to_string(context.max_slice_cells) +
                                                      " (--esdf.max-slice-cells)");
      return;
    }
    const esdf::OccupancyGrid grid = esdf::occupancySlice(field, slice);
    OccupancyGrid& out = reply.value;
    out.frame_id = context.frame_id;
    out.resolution = grid.resolution;
    out.width = static_cast<uint32_t>(grid.width);
    out.height = static_cast<uint32_t>(grid.height);
    out.origin = grid.origin;
    out.z = 0.5 * (request.z_min + request.z_max);
    out.cells = grid.cells;
  });
  return reply;
}

ServiceReply<std::vector<SemanticSample>> handleSemanticDistance(const SemanticDistanceRequest& request,
                                                                 const DistanceQueryContext& context) {
  using Reply = std::vector<SemanticSample>;
  if (!context.field) return refuse<Reply>(ReplyCode::kUnavailable, kNoField);
  if (Status ok = checkLabels(request.labels, context.legend); !ok)
    return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  ReplyCode code;
  if (Status ok = checkPoints(request.points, context.limits, code); !ok) return refuse<Reply>(code, ok.error());
  const auto index = context.field->surfaceIndex(request.labels);
  ServiceReply<Reply> reply;
  for (const auto& s : esdf::semanticDistances(*index, request.points))
    reply.value.push_back({s.found, s.label, s.distance, s.direction, s.surface_point.cast<double>()});
  return reply;
}

ServiceReply<SemanticSlice> handleSemanticSlice(const SemanticSliceRequest& request,
                                                const DistanceQueryContext& context) {
  using Reply = SemanticSlice;
  if (!context.field) return refuse<Reply>(ReplyCode::kUnavailable, kNoField);
  if (Status ok = checkLabels(request.labels, context.legend); !ok)
    return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  if (!finite(request.z)) return refuse<Reply>(ReplyCode::kInvalidArgument, "z must be finite");
  if (!(request.resolution > 0.0) || !finite(request.resolution))
    return refuse<Reply>(ReplyCode::kInvalidArgument, "resolution must be a positive number of metres");
  if (Status ok = checkArea(request.min, request.max, "the slice's box"); !ok)
    return refuse<Reply>(ReplyCode::kInvalidArgument, ok.error());
  esdf::SemanticSliceRequest slice;
  slice.z = request.z;
  slice.bounds = {request.min, request.max};
  slice.resolution = request.resolution;
  const uint64_t cells = esdf::semanticSliceCellCount(slice);
  if (cells > context.max_slice_cells)
    return refuse<Reply>(ReplyCode::kTooLarge, std::to_string(cells) + " cells exceed the limit of " +
                                                   std::to_string(context.max_slice_cells) +
                                                   " (--esdf.max-slice-cells)");
  const auto index = context.field->surfaceIndex(request.labels);
  const esdf::SemanticSlice result = esdf::semanticSlice(*index, slice);
  ServiceReply<Reply> reply;
  reply.value = {result.origin, result.resolution, result.z, result.distance};
  return reply;
}

ServiceReply<std::vector<SegmentResult>> handleSegmentCheck(const SegmentCheckRequest& request,
                                                            const DistanceQueryContext& context) {
  using Reply = std::vector<SegmentResult>;
  if (!context.field) return refuse<Reply>(ReplyCode::kUnavailable, kNoField);
  if (request.segments.empty()) return refuse<Reply>(ReplyCode::kInvalidArgument, "no segments");
  if (request.segments.size() > context.limits.max_points)
    return refuse<Reply>(ReplyCode::kTooLarge, std::to_string(request.segments.size()) +
                                                   " segments exceed the limit of " +
                                                   std::to_string(context.limits.max_points));
  if (!(request.radius >= 0.0) || !finite(request.radius))
    return refuse<Reply>(ReplyCode::kInvalidArgument, "radius must be a finite number >= 0");
  std::vector<esdf::Segment> segments;
  segments.reserve(request.segments.size());
  for (std::size_t i = 0; i < request.segments.size(); ++i) {
    const Segment& s = request.segments[i];
    if (!s.start.allFinite() || !s.end.allFinite())
      return refuse<Reply>(ReplyCode::kInvalidArgument, "segment " + std::to_string(i) + " is not finite");
    segments.push_back({s.start, s.end});
  }
  ServiceReply<Reply> reply;
  std::vector<esdf::SegmentResult> results;
  context.field->read(
      [&](const esdf::EsdfMap& field) { results = esdf::checkSegments(field, segments, request.radius); });
  for (const auto& r : results)
    reply.value.push_back({static_cast<SegmentStatus>(r.status), r.fraction, r.blocked_at, r.min_clearance});
  return reply;
}

OccupancyGrid publishedOccupancyGrid(const DistanceSource& field, const EsdfConfig& config) {
  esdf::OccupancyRequest slice;
  slice.z_min = config.occupancy_min_z;
  slice.z_max = config.occupancy_max_z;
  slice.inflation_radius = config.occupancy_inflation;
  OccupancyGrid out;
  out.frame_id = config.occupancy_frame_id;
  out.z = 0.5 * (slice.z_min + slice.z_max);
  field.read([&](const esdf::EsdfMap& map) {
    const esdf::OccupancyGrid grid = esdf::occupancySlice(map, slice);
    out.resolution = grid.resolution;
    out.width = static_cast<uint32_t>(grid.width);
    out.height = static_cast<uint32_t>(grid.height);
    out.origin = grid.origin;
    out.cells = grid.cells;
  });
  return out;
}

}  // namespace semfuse::server
