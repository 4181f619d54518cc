#pragma once
// The parts of a surface nets vertex and quad that the whole-map mesher (mesh_surface_nets.cpp)
// and the block mesher (mesh_blocks.cpp) share, so that both place every vertex at the same point
// with the same attributes and split every quad the same way.
#include <cstdint>

#include <Eigen/Geometry>

#include "mesh_cells.hpp"
#include "semfuse/volume/cell_interpolation.hpp"
#include "semfuse/volume/voxel.hpp"

namespace semfuse::render::detail {

// Corner k = dx + 2 dy + 4 dz of a cell.
struct CellCorners {
  volume::PackedVoxel packed[8];
  float tsdf[8];
  bool inside[8];
};

// tsdf < 0 read from the half's bits: sign set and magnitude non-zero (-0 is not inside), the
// test the cell classification uses, so that every cell it kept has a crossing.
inline bool insideBits(volume::PackedVoxel v) {
  const auto bits = static_cast<uint64_t>(v);
  return (bits & 0x8000u) != 0 && (bits & 0x7FFFu) != 0;
}

inline void fillCorners(CellCorners& corners) {
  for (int k = 0; k < 8; ++k) {
    corners.tsdf[k] = volume::unpackTsdf(corners.packed[k]);
    corners.inside[k] = insideBits(corners.packed[k]);
  }
}

// The mean of the points where the zero level crosses the cell's edges, in the cell's own
// coordinates ([0, 1]^3), each crossing interpolated linearly along its edge: all crossings, or
// with a topology only those of piece `group` (the few split cells; the others skip the lookups).
inline Eigen::Vector3f meanCrossing(const CellCorners& c, const CellTopology* topology = nullptr, int group = 0) {
  Eigen::Vector3f sum = Eigen::Vector3f::Zero();
  int crossings = 0;
  for (int k = 0; k < 8; ++k)
    for (int axis = 0; axis < 3; ++axis) {
      const int step = 1 << axis;
      if ((k & step) != 0 || c.inside[k] == c.inside[k | step]) continue;
      if (topology != nullptr && topology->group[k][axis] != group) continue;
      float t = c.tsdf[k] / (c.tsdf[k] - c.tsdf[k | step]);
      if (!(t >= 0.0f && t <= 1.0f)) t = 0.5f;  // NaN or inf in a loaded map: keep the vertex in the cell
      Eigen::Vector3f point(static_cast<float>(k & 1), static_cast<float>((k >> 1) & 1),
                            static_cast<float>((k >> 2) & 1));
      point[axis] = t;
      sum += point;
      ++crossings;
    }
  return sum / static_cast<float>(crossings);  // >= 1: every piece crosses an edge
}

// Unit gradient of the trilinear interpolant of the corners at p (cell coordinates): the normal,
// pointing towards free space. Zero where the gradient vanishes.
inline Eigen::Vector3f normalAt(const CellCorners& c, const Eigen::Vector3f& p) {
  Eigen::Vector3f gradient;
  volume::trilinearWithGradient(c.tsdf, p.x(), p.y(), p.z(), gradient);
  const float norm = gradient.norm();
  return norm > 0.0f ? Eigen::Vector3f(gradient / norm) : Eigen::Vector3f::Zero();
}

// The corner nearest to p: the one on the same side of 0.5 on every axis. The vertex takes its
// label, score and colour.
inline int nearestCorner(const Eigen::Vector3f& p) {
  return (p.x() >= 0.5f ? 1 : 0) | (p.y() >= 0.5f ? 2 : 0) | (p.z() >= 0.5f ? 4 : 0);
}

// Which diagonal of quad abcd to split along: the one whose two triangles turn the same way most.
// Vertices sit anywhere in their cells, so a quad can be bent or, seen from its normal, not convex;
// a split along the wrong diagonal then folds one triangle over the other.
inline bool splitAlongAC(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
                         const Eigen::Vector3f& d) {
  auto agreement = [](const Eigen::Vector3f& n1, const Eigen::Vector3f& n2) {
    const float norms = n1.norm() * n2.norm();
    return norms > 0.0f ? n1.dot(n2) / norms : -1.0f;
  };
  const float along_ac = agreement((b - a).cross(c - a), (c - a).cross(d - a));
  const float along_bd = agreement((b - a).cross(d - a), (c - b).cross(d - b));
  return along_ac >= along_bd;
}

}  // namespace semfuse::render::detail
