#include "semfuse/esdf/esdf_params.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace semfuse::esdf {

double EsdfParams::fieldVoxel(double map_voxel, double truncation) const {
  if (voxel_size > 0.0) return voxel_size;
  const double limit = std::min(kAutoVoxel, truncation);
  return map_voxel * std::max(1.0, std::floor(limit / map_voxel * (1.0 + 1e-9)));
}

int EsdfParams::stride(double map_voxel, double truncation) const {
  return static_cast<int>(std::lround(fieldVoxel(map_voxel, truncation) / map_voxel));
}

Status EsdfParams::validate(double map_voxel, double truncation) const {
  if (!(map_voxel > 0.0) || !std::isfinite(map_voxel)) return makeError("voxel size must be positive");
  if (!(voxel_size >= 0.0) || !std::isfinite(voxel_size))
    return makeError("the distance field's voxel size must be positive (or 0: chosen from the map's), got " +
                     std::to_string(voxel_size));
  const double field_voxel = fieldVoxel(map_voxel, truncation);
  const double ratio = field_voxel / map_voxel;
  if (std::abs(ratio - std::round(ratio)) > 1e-6 * ratio || ratio < 1.0 - 1e-6)
    return makeError("the distance field's voxel " + std::to_string(field_voxel) +
                     " m is not a whole multiple of the map's " + std::to_string(map_voxel) + " m");
  if (stride(map_voxel, truncation) > 1 && field_voxel > truncation * (1.0 + 1e-6))
    return makeError("the distance field's voxel " + std::to_string(field_voxel) + " m is larger than the truncation " +
                     std::to_string(truncation) + " m: surfaces could pass between its samples of the TSDF");
  if (!(max_distance > 0.0) || !std::isfinite(max_distance))
    return makeError("the distance field's maximum distance must be positive, got " + std::to_string(max_distance));
  // Offsets to sites are 16-bit voxel counts.
  if (max_distance / field_voxel > 30000.0)
    return makeError("the distance field's maximum distance " + std::to_string(max_distance) +
                     " m is more than 30000 voxels of " + std::to_string(field_voxel) + " m");
  if (!(min_site_weight >= 0.0f)) return makeError("the minimum site weight must be >= 0");
  return Status::Ok();
}

}  // namespace semfuse::esdf
