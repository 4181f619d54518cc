#pragma once
// Semantic distance: how far a point is from the nearest surface of given labels, and in which
// direction, from the labeled surface points the distance field keeps (label_surfaces.hpp). The
// points of the asked labels go into a KD-tree (SurfaceIndex, built in O(n log n), a few ms for
// a table's thousands of points); every query is a nearest-neighbour search in it. Distances are
// unsigned and not limited to the field's maximum distance.
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "semfuse/esdf/distance_queries.hpp"
#include "semfuse/esdf/label_surfaces.hpp"

namespace semfuse::esdf {

class SurfaceIndex {
 public:
  explicit SurfaceIndex(std::vector<SurfacePoint> points);

  struct Nearest {
    bool found = false;  // false only for an empty index
    float distance = 0.0F;
    const SurfacePoint* point = nullptr;
  };
  Nearest nearest(const Eigen::Vector3f& query) const;
  std::size_t size() const { return points_.size(); }

 private:
  void build(std::size_t begin, std::size_t end, int depth);
  void search(std::size_t begin, std::size_t end, const Eigen::Vector3f& query, Nearest& best,
              float& best_squared) const;

  // Implicit tree: the median of [begin, end) at (begin + end) / 2, split on axes_[median].
  std::vector<SurfacePoint> points_;
  std::vector<uint8_t> axes_;
};

// Per point: the nearest surface point of the index's labels. direction is the unit vector from
// the query point towards it (zero when the point is on it).
struct SemanticSample {
  bool found = false;
  float distance = 0.0F;
  Eigen::Vector3f direction = Eigen::Vector3f::Zero();
  Eigen::Vector3f surface_point = Eigen::Vector3f::Zero();
  LabelId label = kUnlabeled;
};
std::vector<SemanticSample> semanticDistances(const SurfaceIndex& index, const std::vector<Eigen::Vector3d>& points);

// The distance to the index's surfaces over a horizontal plane at height z: cell (col, row) has
// its centre at origin + (col + 0.5, row + 0.5) * resolution; CV_32FC1 metres, row 0 at the
// minimum y. Empty index: every cell is +infinity.
struct SemanticSliceRequest {
  double z = 0.5;
  SliceBounds bounds;
  double resolution = 0.05;
};
struct SemanticSlice {
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  double resolution = 0.0;
  double z = 0.0;
  cv::Mat distance;  // CV_32FC1
};
// Cells of a request (for limits).
uint64_t semanticSliceCellCount(const SemanticSliceRequest& request);
SemanticSlice semanticSlice(const SurfaceIndex& index, const SemanticSliceRequest& request);

}  // namespace semfuse::esdf
