#pragma once
// Parameters of the distance field. A plain struct; validate() says what is wrong.
#include "semfuse/core/result.hpp"

namespace semfuse::esdf {

struct EsdfParams {
  // Distances are exact up to here (metres); farther observed voxels report this distance and
  // "no site in range". A planner's clearance horizon: nvblox and voxblox default to 2 m.
  double max_distance = 2.0;
  // A voxel is a surface site when the TSDF changes sign between it and a 6-neighbour (both
  // observed) and it has at least this integration weight; its side of the surface (the sign)
  // says whether it seeds free space or the inside of an object.
  float min_site_weight = 0.0f;
  // The field's voxel edge (metres). A field coarser than the map reads the map's TSDF at every
  // `stride`-th voxel along each axis, so it must be a whole multiple of the map's voxel, and at
  // most the truncation: then the band holds a sample on each side of every surface. 0 chooses
  // the coarsest such voxel up to kAutoVoxel (a 1 cm map with 4 cm truncation gets 4 cm; a 5 cm
  // map keeps 5 cm): planners and costmaps work at about 5 cm (Nav2's costmap, nvblox), and the
  // field's cost falls with the cube of its voxel.
  double voxel_size = 0.0;
  static constexpr double kAutoVoxel = 0.05;

  // The field's voxel edge for a map of `map_voxel` metres and that truncation.
  double fieldVoxel(double map_voxel, double truncation) const;
  // Map voxels per field voxel along an axis (1 when the field has the map's voxels).
  int stride(double map_voxel, double truncation) const;

  // Checks the parameters against the map's voxel edge and truncation (metres).
  Status validate(double map_voxel, double truncation) const;
};

}  // namespace semfuse::esdf
