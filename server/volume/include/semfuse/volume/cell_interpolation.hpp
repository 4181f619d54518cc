#pragma once
// The trilinear interpolant inside one voxel cell (the 2x2x2 voxels from a base voxel), for every
// reader of the TSDF: the sampler (tracking, queries), the raycasts and the mesher. Corner
// k = dx + 2 dy + 4 dz; (fx, fy, fz) in [0, 1] is the point's offset from the base voxel.
#include <Eigen/Core>

namespace semfuse::volume {

// Offsets of the 8 corners of a cell inside one OpenVDB leaf buffer (z fastest: 64 x + 8 y + z),
// for a base voxel whose cell lies wholly in that leaf.
inline constexpr int kCellCornerOffsets[8] = {0, 64, 8, 72, 1, 65, 9, 73};

inline float trilinear(const float v[8], float fx, float fy, float fz) {
  const float a00 = v[0] + (v[1] - v[0]) * fx, a10 = v[2] + (v[3] - v[2]) * fx;
  const float a01 = v[4] + (v[5] - v[4]) * fx, a11 = v[6] + (v[7] - v[6]) * fx;
  const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
  return b0 + (b1 - b0) * fz;
}

// The same value, and its analytic gradient per unit of cell coordinates (divide by the voxel
// size for metres): exact for the model the value comes from, so tracking's Jacobian and the
// normals of raycasts and meshes match the surface they are found on.
inline float trilinearWithGradient(const float v[8], float fx, float fy, float fz, Eigen::Vector3f& gradient) {
  // Differences along x for the four (y, z) edges.
  const float dx00 = v[1] - v[0], dx10 = v[3] - v[2], dx01 = v[5] - v[4], dx11 = v[7] - v[6];
  const float a00 = v[0] + dx00 * fx, a10 = v[2] + dx10 * fx;
  const float a01 = v[4] + dx01 * fx, a11 = v[6] + dx11 * fx;
  const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
  gradient = Eigen::Vector3f((1 - fz) * (dx00 + (dx10 - dx00) * fy) + fz * (dx01 + (dx11 - dx01) * fy),
                             (1 - fz) * (a10 - a00) + fz * (a11 - a01), b1 - b0);
  return b0 + (b1 - b0) * fz;
}

}  // namespace semfuse::volume
