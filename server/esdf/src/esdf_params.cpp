#include "semfuse/esdf/esdf_params.hpp"

#include <cmath>
#include <string>

namespace semfuse::esdf {

Status EsdfParams::validate(double voxel_size) const {
  if (!(voxel_size > 0.0) || !std::isfinite(voxel_size)) return makeError("voxel size must be positive");
  if (!(max_distance > 0.0) || !std::isfinite(max_distance))
    return makeError("the distance field's maximum distance must be positive, got " + std::to_string(max_distance));
  // Offsets to sites are 16-bit voxel counts.
  if (max_distance / voxel_size > 30000.0)
    return makeError("the distance field's maximum distance " + std::to_string(max_distance) +
                     " m is more than 30000 voxels of " + std::to_string(voxel_size) + " m");
  if (!(min_site_weight >= 0.0f)) return makeError("the minimum site weight must be >= 0");
  return Status::Ok();
}

}  // namespace semfuse::esdf
