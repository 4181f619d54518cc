#include "distance_arrays.hpp"

#include <string>

#include "arrays.hpp"

namespace semfuse::python {
namespace {

// (N, 3) of T from Eigen vectors, by a member of each element.
template <class T, class Sample, class Get>
py::array_t<T> vectorsOf(const std::vector<Sample>& samples, Get get) {
  py::array_t<T> out({static_cast<py::ssize_t>(samples.size()), py::ssize_t{3}});
  auto view = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const auto& v = get(samples[i]);
    for (py::ssize_t k = 0; k < 3; ++k) view(static_cast<py::ssize_t>(i), k) = static_cast<T>(v[k]);
  }
  return out;
}

template <class T, class Sample, class Get>
py::array_t<T> valuesOf(const std::vector<Sample>& samples, Get get) {
  py::array_t<T> out(static_cast<py::ssize_t>(samples.size()));
  auto view = out.template mutable_unchecked<1>();
  for (std::size_t i = 0; i < samples.size(); ++i) view(static_cast<py::ssize_t>(i)) = static_cast<T>(get(samples[i]));
  return out;
}

py::array_t<double> planeArray(const Eigen::Vector2d& p) {
  py::array_t<double> out(2);
  out.mutable_at(0) = p.x();
  out.mutable_at(1) = p.y();
  return out;
}

}  // namespace

py::dict distanceSamplesDict(const std::vector<client::DistanceSample>& samples) {
  using S = client::DistanceSample;
  py::dict out;
  out["known"] = valuesOf<bool>(samples, [](const S& s) { return s.known; });
  out["beyond"] = valuesOf<bool>(samples, [](const S& s) { return s.beyond; });
  out["distance"] = valuesOf<float>(samples, [](const S& s) { return s.distance; });
  out["gradient"] = vectorsOf<float>(
      samples, [](const S& s) -> const auto& { return s.gradient; });
  return out;
}

py::dict occupancyGridDict(client::OccupancyGrid grid) {
  py::dict out;
  out["cells"] = vectorToArray(std::move(grid.cells),
                               {static_cast<py::ssize_t>(grid.height), static_cast<py::ssize_t>(grid.width)});
  out["resolution"] = grid.resolution;
  out["origin"] = planeArray(grid.origin);
  out["z"] = grid.z;
  out["frame_id"] = grid.frame_id;
  return out;
}

py::dict semanticSamplesDict(const std::vector<client::SemanticSample>& samples) {
  using S = client::SemanticSample;
  py::dict out;
  out["found"] = valuesOf<bool>(samples, [](const S& s) { return s.found; });
  out["label"] = valuesOf<uint16_t>(samples, [](const S& s) { return s.label; });
  out["distance"] = valuesOf<float>(samples, [](const S& s) { return s.distance; });
  out["direction"] = vectorsOf<float>(
      samples, [](const S& s) -> const auto& { return s.direction; });
  out["surface_point"] = vectorsOf<double>(
      samples, [](const S& s) -> const auto& { return s.surface_point; });
  return out;
}

py::dict semanticSliceDict(const client::SemanticSlice& slice) {
  py::dict out;
  out["distance"] = imageToArray(slice.distance);
  out["min"] = planeArray(slice.min);
  out["resolution"] = slice.resolution;
  out["z"] = slice.z;
  return out;
}

py::dict segmentResultsDict(const std::vector<client::SegmentResult>& results) {
  using R = client::SegmentResult;
  py::dict out;
  out["status"] = valuesOf<uint8_t>(results, [](const R& r) { return static_cast<uint8_t>(r.status); });
  out["fraction"] = valuesOf<float>(results, [](const R& r) { return r.fraction; });
  out["blocked_at"] = vectorsOf<double>(
      results, [](const R& r) -> const auto& { return r.blocked_at; });
  out["min_clearance"] = valuesOf<float>(results, [](const R& r) { return r.min_clearance; });
  return out;
}

std::vector<client::Segment> segmentsFromArrays(const py::handle& starts, const py::handle& ends) {
  const auto from = pointsFromArray(starts, "starts");
  const auto to = pointsFromArray(ends, "ends");
  if (from.size() != to.size())
    throw py::value_error("starts and ends must have as many points (" + std::to_string(from.size()) + " and " +
                          std::to_string(to.size()) + ")");
  std::vector<client::Segment> segments(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) segments[i] = {from[i], to[i]};
  return segments;
}

Eigen::Vector2d planePointFromArray(const py::handle& object, const char* what) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(object);
  if (!a || a.ndim() != 1 || a.shape(0) != 2) throw py::value_error(std::string(what) + " must be 2 numbers x, y");
  const Eigen::Vector2d p(a.at(0), a.at(1));
  if (!p.allFinite()) throw py::value_error(std::string(what) + " is not finite");
  return p;
}

}  // namespace semfuse::python
