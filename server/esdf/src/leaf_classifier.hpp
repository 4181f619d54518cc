#pragma once
// What a changed leaf's voxels are now: known or not, inside or not, surface site or not, and a
// site's distance to the surface.
//
// A site is an observed voxel with a 6-neighbour observed on the other side of the surface: a zero
// crossing lies on the edge between them, wherever the projective TSDF's magnitudes put it (at
// grazing views |tsdf| is several times the true distance, but the crossing stays where the
// surface is). Linearly interpolated, it lies |t| / (|t| + |t_neighbour|) of a voxel along the
// edge. The site's distance is to the plane through its crossings, one per axis (the nearer one
// where both edges of an axis cross): with crossings at fractions a, b, c of a voxel along the
// axes, the plane lies 1 / sqrt(1/a^2 + 1/b^2 + 1/c^2) from the voxel's centre (an axis without a
// crossing adds nothing). The nearest crossing alone would overestimate the distance to an
// oblique surface by up to sqrt(3) (a sphere's rim, a rotated box's faces).
#include <array>
#include <cstdint>
#include <vector>

#include "semfuse/esdf/esdf_params.hpp"
#include "semfuse/esdf/label_surfaces.hpp"
#include "semfuse/esdf/map_changes.hpp"

namespace semfuse::esdf::detail {

struct Classified {
  bool known = false;
  bool inside = false;
  bool site = false;
  uint8_t site_distance = 0;  // 1/255 voxel
};

class LeafClassifier {
 public:
  LeafClassifier(double voxel_size, const EsdfParams& params);

  // Classifies every voxel of the leaf (index = OpenVDB leaf offset); false when none is known.
  bool classify(const ChangedLeaf& leaf, std::array<Classified, volume::LabeledVolume::kLeafVoxels>& out);
  // The labeled surface points of the leaf last classified: for every free-side site with a
  // label, the zero crossing on its nearest crossing edge (a point of the surface: the plane's
  // nearest point would cut the corners of boxes).
  std::vector<SurfacePoint> surfacePoints(const ChangedLeaf& leaf) const;

 private:
  static constexpr int kDim = volume::LabeledVolume::kLeafDim;
  static constexpr int kPadded = kDim + 2;

  struct Crossing {
    int axis = -1;  // the nearest crossing's edge; -1: no neighbour across the surface
    int direction = 0;
    float fraction = 1.0f;
    float distance = 1.0f;  // to the plane through the crossings, voxels
  };

  // Index into tsdf_ of local (x, y, z), each in -1..kDim (the halo).
  static int padded(int x, int y, int z) { return ((x + 1) * kPadded + (y + 1)) * kPadded + (z + 1); }
  Crossing nearestCrossing(int x, int y, int z) const;

  float voxel_, min_weight_;
  // The leaf's TSDF and the layer just outside each face, NaN where unobserved: every voxel's
  // 6 neighbours are one array read away.
  std::array<float, kPadded * kPadded * kPadded> tsdf_{};
};

// A changed leaf classified: its voxels (index = OpenVDB leaf offset) and labeled surface points.
struct ClassifiedLeaf {
  bool any_known = false;
  std::array<Classified, volume::LabeledVolume::kLeafVoxels> voxels;
  std::vector<SurfacePoint> surface;
};

// The changed leaves classified in parallel, leaves[i] from changed[i]: a leaf's classification
// reads its own copy alone (voxels and halo), while writing the field and queueing the waves is
// one sequence.
struct ClassifiedLeaves {
  std::vector<ClassifiedLeaf> leaves;
  void classify(const std::vector<ChangedLeaf>& changed, double voxel_size, const EsdfParams& params);
};

}  // namespace semfuse::esdf::detail
