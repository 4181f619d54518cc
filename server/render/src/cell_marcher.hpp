#pragma once
// One ray through the crossing cells of raycast()'s fast path. Internal.
//
// The ray walks the voxel cells it passes through, in order (a 3D DDA in index space, voxel
// (i, j, k) centred at (i, j, k), cell (i, j, k) spanning [i, i + 1] x [j, j + 1] x [k, k + 1]).
// Cells that are not crossing cells (CrossingCells) cost one bit test. In a crossing cell the
// trilinear TSDF is evaluated where the ray enters and where it leaves; positive then
// non-positive is the surface, located on the cubic that the interpolant is along the ray
// (secant, then Newton). Compared with stepping by samples, the first crossing along the ray is
// found exactly at cell granularity, and no voxel is read outside crossing cells.
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "crossing_cells.hpp"
#include "ray_marcher.hpp"

namespace semfuse::render::detail {

// Where a ray meets the surface, with what shading needs: the TSDF (metres) of the cell's 8
// corners (corner k = dx + 2 dy + 4 dz), the hit point inside the cell, and where the cell is
// (its other layers are read from the leaf, for the corner nearest to the hit only).
struct SurfaceHit {
  double t = 0.0;  // camera depth
  float tsdf[8] = {};
  float fraction[3] = {};                          // hit point minus the cell's base voxel, each in [0, 1]
  const CrossingCells::LeafCells* leaf = nullptr;  // the leaf of the cell's base voxel
  int local[3] = {};                               // the base voxel in that leaf
};

// Marches rays through the crossing cells of one CrossingCells (findCrossings() done).
class CellMarcher {
 public:
  CellMarcher(const CrossingCells& cells, double voxel_size) : cells_(&cells), inv_voxel_size_(1.0 / voxel_size) {}

  // The first positive-to-non-positive crossing of the trilinear TSDF in [t_min, t_max); false
  // when none.
  bool findSurface(const MarchRay& ray, SurfaceHit& hit) const;

 private:
  const CrossingCells* cells_;
  double inv_voxel_size_;
};

}  // namespace semfuse::render::detail
