#pragma once
// Per-tile camera-depth bounds of the observed leaves, for raycast(). Internal.
//
// Every leaf that holds an observed voxel is projected into the image (its index-space box
// [origin, origin + 8]^3, which holds every point a valid trilinear sample based in that leaf can
// take); each square tile of pixels keeps the smallest and largest camera depth of the leaves
// whose projection covers one of its pixel centres. A ray can then start at its tile's near
// bound and stop at its far bound: the free space in front of the first leaf, and the space
// behind the last one, need no marching at all. Conservative by construction (the projection of
// a box in front of the camera is the convex hull of its projected corners); a leaf that reaches
// behind the camera plane opens every tile from the near clip on.
#include <vector>

#include "semfuse/core/types.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::render::detail {

class TileDepthBounds {
 public:
  static constexpr int kTileSize = 8;  // pixels per tile edge

  // Bounds of `volume`'s observed leaves seen by `camera_to_world` with intrinsics `k`, limited
  // to [min_depth, max_depth].
  TileDepthBounds(const volume::LabeledVolume& volume, const PinholeIntrinsics& k, const Pose& camera_to_world,
                  double min_depth, double max_depth);

  // Camera-depth interval of pixel (u, v) that can hold a surface; false when no leaf covers it.
  bool depthRange(int u, int v, double& near, double& far) const {
    const Range& r = tiles_[static_cast<std::size_t>(v / kTileSize) * tiles_x_ + u / kTileSize];
    if (!(r.near <= r.far)) return false;
    near = r.near;
    far = r.far;
    return true;
  }

 private:
  struct Range {
    float near;  // +inf while no leaf covers the tile
    float far;
  };
  int tiles_x_ = 0;
  int tiles_y_ = 0;
  std::vector<Range> tiles_;
};

}  // namespace semfuse::render::detail
