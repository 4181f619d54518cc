#include "semfuse/esdf/distance_queries.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

namespace semfuse::esdf {
namespace {

// Per-thread reader of the field: accessor-cached voxel reads, the trilinear interpolant.
class FieldSampler {
 public:
  explicit FieldSampler(const EsdfMap& map)
      : values_(map.grid().tree()), voxel_(static_cast<float>(map.voxelSize())), max_voxels_(map.maxDistanceVoxels()) {}

  bool voxel(const openvdb::Coord& ijk, EsdfVoxel& out) {
    PackedEsdf packed;
    if (!values_.probeValue(ijk, packed)) return false;
    out = unpackEsdf(packed);
    return true;
  }

  // Signed distance in metres of one voxel, false where unknown.
  bool voxelDistance(const openvdb::Coord& ijk, float& distance, bool& beyond) {
    EsdfVoxel v;
    if (!voxel(ijk, v)) return false;
    distance = v.signedDistance(max_voxels_) * voxel_;
    beyond = !v.has_site;
    return true;
  }

  DistanceSample sample(const Eigen::Vector3d& world) {
    DistanceSample out;
    if (!world.allFinite()) return out;
    const Eigen::Vector3d p = world / static_cast<double>(voxel_);
    constexpr double kEdge = 2.0e9;  // beyond OpenVDB's int coordinates: never observed
    if ((p.array().abs() > kEdge).any()) return out;
    const openvdb::Coord base(static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())),
                              static_cast<int>(std::floor(p.z())));
    const float fx = static_cast<float>(p.x() - base.x()), fy = static_cast<float>(p.y() - base.y()),
                fz = static_cast<float>(p.z() - base.z());
    float d[8];
    bool all_known = true, all_beyond = true;
    for (int c = 0; c < 8 && all_known; ++c) {
      bool beyond = false;
      all_known = voxelDistance(base.offsetBy(c & 1, (c >> 1) & 1, (c >> 2) & 1), d[c], beyond);
      all_beyond = all_beyond && beyond;
    }
    if (all_known) {
      // Trilinear interpolation (corner c = x bit 0, y bit 1, z bit 2) and its gradient.
      const float x00 = d[0] + (d[1] - d[0]) * fx, x10 = d[2] + (d[3] - d[2]) * fx;
      const float x01 = d[4] + (d[5] - d[4]) * fx, x11 = d[6] + (d[7] - d[6]) * fx;
      const float y0 = x00 + (x10 - x00) * fy, y1 = x01 + (x11 - x01) * fy;
      out.distance = y0 + (y1 - y0) * fz;
      const float gx = ((d[1] - d[0]) * (1 - fy) + (d[3] - d[2]) * fy) * (1 - fz) +
                       ((d[5] - d[4]) * (1 - fy) + (d[7] - d[6]) * fy) * fz;
      const float gy = (x10 - x00) * (1 - fz) + (x11 - x01) * fz;
      const float gz = y1 - y0;
      const Eigen::Vector3f gradient(gx, gy, gz);
      out.known = true;
      out.beyond = all_beyond;
      // Per voxel the field changes by up to a voxel's length; a flatter interpolant (a ridge
      // between two sites, or a region beyond the maximum) has no usable direction.
      if (gradient.norm() > 0.1f * voxel_) out.gradient = gradient.normalized();
      else out.gradient = siteDirection(p);
      return out;
    }
    const openvdb::Coord nearest(static_cast<int>(std::floor(p.x() + 0.5)), static_cast<int>(std::floor(p.y() + 0.5)),
                                 static_cast<int>(std::floor(p.z() + 0.5)));
    bool beyond = false;
    if (!voxelDistance(nearest, out.distance, beyond)) return out;
    out.known = true;
    out.beyond = beyond;
    out.gradient = siteDirection(p);
    return out;
  }

 private:
  // The unit direction away from the nearest voxel's site (towards it inside); zero without one.
  Eigen::Vector3f siteDirection(const Eigen::Vector3d& p) {
    const openvdb::Coord nearest(static_cast<int>(std::floor(p.x() + 0.5)), static_cast<int>(std::floor(p.y() + 0.5)),
                                 static_cast<int>(std::floor(p.z() + 0.5)));
    EsdfVoxel v;
    if (!voxel(nearest, v) || !v.has_site) return Eigen::Vector3f::Zero();
    const openvdb::Coord site = v.site(nearest);
    Eigen::Vector3f away(static_cast<float>(p.x() - site.x()), static_cast<float>(p.y() - site.y()),
                         static_cast<float>(p.z() - site.z()));
    if (away.norm() < 1e-6f) return Eigen::Vector3f::Zero();
    away.normalize();
    return v.inside ? Eigen::Vector3f(-away) : away;
  }

  openvdb::tree::ValueAccessor<const EsdfGrid::TreeType> values_;
  float voxel_, max_voxels_;
};

// A point takes about 0.1 us: a planner's batch of this many is done in a few ms on the calling
// thread. Split over TBB's workers, its median halves but its p95 grows several-fold on a loaded
// machine (the call waits for a chunk whose worker was descheduled).
constexpr std::size_t kSequentialPoints = 32768;

int indexOf(double metres, double voxel) { return static_cast<int>(std::floor(metres / voxel + 0.5)); }

// Voxel index ranges (inclusive) of a slice request.
struct SliceIndices {
  openvdb::Coord min, max;
  bool empty = true;
};
SliceIndices sliceIndices(const EsdfMap& map, const OccupancyRequest& request) {
  SliceIndices s;
  const double h = map.voxelSize();
  if (request.bounds) {
    s.min = {indexOf(request.bounds->min.x(), h), indexOf(request.bounds->min.y(), h), 0};
    s.max = {indexOf(request.bounds->max.x(), h), indexOf(request.bounds->max.y(), h), 0};
  } else {
    const openvdb::CoordBBox box = map.grid().evalActiveVoxelBoundingBox();
    if (box.empty()) return s;
    s.min = {box.min().x(), box.min().y(), 0};
    s.max = {box.max().x(), box.max().y(), 0};
  }
  // The voxel layers whose centres lie in the band; a band thinner than a voxel takes the layer
  // nearest its middle.
  int z0 = static_cast<int>(std::ceil(request.z_min / h - 1e-9)),
      z1 = static_cast<int>(std::floor(request.z_max / h + 1e-9));
  if (z1 < z0) z0 = z1 = indexOf(0.5 * (request.z_min + request.z_max), h);
  s.min.z() = z0;
  s.max.z() = z1;
  s.empty = s.max.x() < s.min.x() || s.max.y() < s.min.y();
  return s;
}

}  // namespace

std::vector<DistanceSample> distancesAt(const EsdfMap& map, const std::vector<Eigen::Vector3d>& points) {
  std::vector<DistanceSample> out(points.size());
  if (points.size() <= kSequentialPoints) {
    FieldSampler sampler(map);
    for (std::size_t i = 0; i < points.size(); ++i) out[i] = sampler.sample(points[i]);
    return out;
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 512),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      FieldSampler sampler(map);
                      for (std::size_t i = range.begin(); i != range.end(); ++i) out[i] = sampler.sample(points[i]);
                    });
  return out;
}

uint64_t occupancyCellCount(const EsdfMap& map, const OccupancyRequest& request) {
  const SliceIndices s = sliceIndices(map, request);
  if (s.empty) return 0;
  return uint64_t(s.max.x() - s.min.x() + 1) * uint64_t(s.max.y() - s.min.y() + 1);
}

OccupancyGrid occupancySlice(const EsdfMap& map, const OccupancyRequest& request) {
  OccupancyGrid grid;
  const double h = map.voxelSize();
  grid.resolution = h;
  grid.z_min = request.z_min;
  grid.z_max = request.z_max;
  const SliceIndices s = sliceIndices(map, request);
  if (s.empty) return grid;
  grid.width = s.max.x() - s.min.x() + 1;
  grid.height = s.max.y() - s.min.y() + 1;
  grid.origin = {(s.min.x() - 0.5) * h, (s.min.y() - 0.5) * h};
  grid.cells.assign(static_cast<std::size_t>(grid.width) * grid.height, kCellUnknown);
  const float max_voxels = map.maxDistanceVoxels();
  tbb::parallel_for(tbb::blocked_range<int>(0, grid.height, 4), [&](const tbb::blocked_range<int>& rows) {
    FieldSampler sampler(map);
    for (int row = rows.begin(); row != rows.end(); ++row) {
      for (int col = 0; col < grid.width; ++col) {
        bool occupied = false, all_known = true;
        for (int z = s.min.z(); z <= s.max.z() && !occupied; ++z) {
          EsdfVoxel v;
          if (!sampler.voxel({s.min.x() + col, s.min.y() + row, z}, v)) {
            all_known = false;
            continue;
          }
          occupied = v.signedDistance(max_voxels) < 0.5f;
        }
        grid.cells[static_cast<std::size_t>(row) * grid.width + col] =
            occupied ? kCellOccupied : (all_known ? kCellFree : kCellUnknown);
      }
    }
  });
  if (request.inflation_radius > 0.0) {
    // Distance of every cell to the nearest occupied one (exact Euclidean, in cells).
    cv::Mat not_occupied(grid.height, grid.width, CV_8UC1);
    for (int i = 0; i < grid.height * grid.width; ++i) not_occupied.data[i] = grid.cells[i] == kCellOccupied ? 0 : 255;
    cv::Mat distance;
    cv::distanceTransform(not_occupied, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    const float radius_cells = static_cast<float>(request.inflation_radius / h);
    for (int i = 0; i < grid.height * grid.width; ++i)
      if (grid.cells[i] == kCellFree && distance.ptr<float>()[i] <= radius_cells) grid.cells[i] = kCellInflated;
  }
  return grid;
}

std::vector<SegmentResult> checkSegments(const EsdfMap& map, const std::vector<Segment>& segments, double radius) {
  std::vector<SegmentResult> out(segments.size());
  const double h = map.voxelSize();
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, segments.size(), 16), [&](const tbb::blocked_range<std::size_t>& range) {
        FieldSampler sampler(map);
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
          const Segment& segment = segments[i];
          SegmentResult& result = out[i];
          const Eigen::Vector3d delta = segment.end - segment.start;
          const double length = delta.norm();
          result.min_clearance = std::numeric_limits<float>::infinity();
          double t = 0.0;  // metres along the segment
          for (;;) {
            const Eigen::Vector3d at =
                length > 0.0 ? Eigen::Vector3d(segment.start + delta * (t / length)) : segment.start;
            const DistanceSample s = sampler.sample(at);
            const SegmentStatus failed =
                !s.known ? SegmentStatus::kUnknown
                         : (s.distance <= radius ? SegmentStatus::kCollision : SegmentStatus::kFree);
            if (s.known) result.min_clearance = std::min(result.min_clearance, static_cast<float>(s.distance - radius));
            if (failed != SegmentStatus::kFree) {
              result.status = failed;
              result.fraction = length > 0.0 ? static_cast<float>(t / length) : 0.0F;
              result.blocked_at = at;
              break;
            }
            if (t >= length) break;
            t = std::min(length, t + std::max(s.distance - radius - h, 0.5 * h));
          }
          if (!std::isfinite(result.min_clearance)) result.min_clearance = 0.0F;
        }
      });
  return out;
}

}  // namespace semfuse::esdf
