#include "label_metric.hpp"

#include <cstdint>

namespace semfuse::eval {

std::vector<openvdb::Coord> surfaceVoxels(const volume::LabeledVolume& volume) {
  std::vector<openvdb::Coord> surface;
  auto accessor = volume.geometryGrid().getConstAccessor();
  for (auto it = volume.geometryGrid().cbeginValueOn(); it; ++it) {
    const volume::PackedVoxel v = *it;
    if (!volume::isObserved(v)) continue;
    const bool inside = volume::unpackTsdf(v) < 0.0f;
    const openvdb::Coord c = it.getCoord();
    for (const openvdb::Coord& step : {openvdb::Coord(1, 0, 0), openvdb::Coord(-1, 0, 0), openvdb::Coord(0, 1, 0),
                                       openvdb::Coord(0, -1, 0), openvdb::Coord(0, 0, 1), openvdb::Coord(0, 0, -1)}) {
      const volume::PackedVoxel n = accessor.getValue(c + step);
      if (volume::isObserved(n) && (volume::unpackTsdf(n) < 0.0f) != inside) {
        surface.push_back(c);
        break;
      }
    }
  }
  return surface;
}

LabelError volumetricLabelError(const volume::LabeledVolume& reference, const volume::LabeledVolume& test,
                                const std::vector<openvdb::Coord>& voxels) {
  LabelError error;
  auto ref = reference.geometryGrid().getConstAccessor();
  auto got = test.geometryGrid().getConstAccessor();
  for (const openvdb::Coord& c : voxels) {
    const LabelId expected = volume::unpackLabel(ref.getValue(c));
    if (expected == kUnlabeled) continue;
    ++error.compared;
    error.wrong += volume::unpackLabel(got.getValue(c)) != expected;
  }
  return error;
}

Result<LabelError> pixelLabelError(const cv::Mat& reference, const cv::Mat& labels) {
  if (reference.type() != CV_16UC1 || labels.type() != CV_16UC1) return makeError("label images must be CV_16UC1");
  if (reference.size() != labels.size())
    return makeError("label image is " + std::to_string(labels.cols) + "x" + std::to_string(labels.rows) +
                     ", the reference " + std::to_string(reference.cols) + "x" + std::to_string(reference.rows));
  LabelError error;
  for (int r = 0; r < reference.rows; ++r) {
    const auto* ref = reference.ptr<uint16_t>(r);
    const auto* got = labels.ptr<uint16_t>(r);
    for (int c = 0; c < reference.cols; ++c) {
      if (ref[c] == kUnlabeled) continue;
      ++error.compared;
      error.wrong += got[c] != ref[c];
    }
  }
  return error;
}

}  // namespace semfuse::eval
