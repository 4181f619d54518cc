#include "semfuse/esdf/semantic_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace semfuse::esdf {

SurfaceIndex::SurfaceIndex(std::vector<SurfacePoint> points) : points_(std::move(points)), axes_(points_.size(), 0) {
  build(0, points_.size(), 0);
}

void SurfaceIndex::build(std::size_t begin, std::size_t end, int depth) {
  if (end - begin <= 1) return;
  // Split on the axis of the widest extent: better than cycling for walls and table tops.
  Eigen::Vector3f lo = points_[begin].position, hi = lo;
  for (std::size_t i = begin + 1; i < end; ++i) {
    lo = lo.cwiseMin(points_[i].position);
    hi = hi.cwiseMax(points_[i].position);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::size_t median = (begin + end) / 2;
  std::nth_element(
      points_.begin() + static_cast<std::ptrdiff_t>(begin), points_.begin() + static_cast<std::ptrdiff_t>(median),
      points_.begin() + static_cast<std::ptrdiff_t>(end),
      [axis](const SurfacePoint& a, const SurfacePoint& b) { return a.position[axis] < b.position[axis]; });
  axes_[median] = static_cast<uint8_t>(axis);
  build(begin, median, depth + 1);
  build(median + 1, end, depth + 1);
}

void SurfaceIndex::search(std::size_t begin, std::size_t end, const Eigen::Vector3f& query, Nearest& best,
                          float& best_squared) const {
  if (begin >= end) return;
  const std::size_t median = (begin + end) / 2;
  const SurfacePoint& p = points_[median];
  const float squared = (p.position - query).squaredNorm();
  if (squared < best_squared) {
    best_squared = squared;
    best.point = &p;
  }
  if (end - begin == 1) return;
  const int axis = axes_[median];
  const float offset = query[axis] - p.position[axis];
  const bool left_first = offset < 0.0f;
  if (left_first) search(begin, median, query, best, best_squared);
  else search(median + 1, end, query, best, best_squared);
  if (offset * offset < best_squared) {
    if (left_first) search(median + 1, end, query, best, best_squared);
    else search(begin, median, query, best, best_squared);
  }
}

SurfaceIndex::Nearest SurfaceIndex::nearest(const Eigen::Vector3f& query) const {
  Nearest best;
  if (points_.empty()) return best;
  float best_squared = std::numeric_limits<float>::infinity();
  search(0, points_.size(), query, best, best_squared);
  best.found = best.point != nullptr;
  best.distance = std::sqrt(best_squared);
  return best;
}

std::vector<SemanticSample> semanticDistances(const SurfaceIndex& index, const std::vector<Eigen::Vector3d>& points) {
  std::vector<SemanticSample> out(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t i = range.begin(); i != range.end(); ++i) {
                        if (!points[i].allFinite()) continue;
                        const Eigen::Vector3f query = points[i].cast<float>();
                        const SurfaceIndex::Nearest nearest = index.nearest(query);
                        if (!nearest.found) continue;
                        SemanticSample& s = out[i];
                        s.found = true;
                        s.distance = nearest.distance;
                        s.surface_point = nearest.point->position;
                        s.label = nearest.point->label;
                        if (nearest.distance > 1e-6f) s.direction = (s.surface_point - query) / nearest.distance;
                      }
                    });
  return out;
}

namespace {
int cellsAlong(double from, double to, double resolution) {
  return std::max(1, static_cast<int>(std::ceil((to - from) / resolution - 1e-9)));
}
}  // namespace

uint64_t semanticSliceCellCount(const SemanticSliceRequest& request) {
  const SliceBounds& b = request.bounds;
  return uint64_t(cellsAlong(b.min.x(), b.max.x(), request.resolution)) *
         uint64_t(cellsAlong(b.min.y(), b.max.y(), request.resolution));
}

SemanticSlice semanticSlice(const SurfaceIndex& index, const SemanticSliceRequest& request) {
  SemanticSlice slice;
  slice.origin = request.bounds.min;
  slice.resolution = request.resolution;
  slice.z = request.z;
  const int width = cellsAlong(request.bounds.min.x(), request.bounds.max.x(), request.resolution);
  const int height = cellsAlong(request.bounds.min.y(), request.bounds.max.y(), request.resolution);
  slice.distance.create(height, width, CV_32FC1);
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 4), [&](const tbb::blocked_range<int>& rows) {
    for (int row = rows.begin(); row != rows.end(); ++row) {
      float* out = slice.distance.ptr<float>(row);
      for (int col = 0; col < width; ++col) {
        const Eigen::Vector3f query(static_cast<float>(slice.origin.x() + (col + 0.5) * request.resolution),
                                    static_cast<float>(slice.origin.y() + (row + 0.5) * request.resolution),
                                    static_cast<float>(request.z));
        const SurfaceIndex::Nearest nearest = index.nearest(query);
        out[col] = nearest.found ? nearest.distance : std::numeric_limits<float>::infinity();
      }
    }
  });
  return slice;
}

}  // namespace semfuse::esdf
