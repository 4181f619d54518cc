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

  Status validate(double voxel_size) const;
};

}  // namespace semfuse::esdf
