#include "leaf_scanner.hpp"

#include <array>
#include <cmath>
#include <limits>

namespace semfuse::objects::detail {
namespace {

// The TSDF of an observed voxel, NaN for an unobserved one.
float tsdfOrNaN(volume::PackedVoxel v) {
  return volume::isObserved(v) ? volume::detail::halfValueBranchless(volume::detail::asBits(v))
                               : std::numeric_limits<float>::quiet_NaN();
}

// Central difference where both neighbours are observed, one-sided where one is, 0 otherwise.
float derivative(float minus, float centre, float plus) {
  const bool has_minus = !std::isnan(minus), has_plus = !std::isnan(plus);
  if (has_minus && has_plus) return 0.5f * (plus - minus);
  if (has_plus) return plus - centre;
  if (has_minus) return centre - minus;
  return 0.0f;
}

// The crossings along one axis that the voxel with TSDF t owns, of those with its two neighbours
// (0, 1 or 2): of two observed neighbours whose TSDF changes sign, the one nearer to zero (the
// outside one on a tie). Comparisons with NaN are false, so unobserved neighbours own nothing.
int ownedCrossings(float t, float minus, float plus) {
  const bool inside = t < 0.0f;
  const float mine = std::abs(t);
  int owned = 0;
  for (float other : {minus, plus}) {
    // A sign change: other is on the other side of zero (never true for NaN).
    const bool crosses = inside ? other >= 0.0f : other < 0.0f;
    if (!crosses) continue;
    const float theirs = std::abs(other);
    owned += mine < theirs || (mine == theirs && !inside);
  }
  return owned;
}

}  // namespace

// A leaf's TSDF with a one-voxel rim from its six face neighbours, so that every lookup of the
// scan is an array read. NaN marks an unobserved voxel. Laid out as the leaf is (z fastest), so
// that loading a row of the leaf is a contiguous copy.
class LeafScanner::Brick {
 public:
  static constexpr int kSide = kLeafDim + 2;

  void load(const volume::GeometryGrid::TreeType& tree, const GeometryLeaf& leaf) {
    values_.fill(std::numeric_limits<float>::quiet_NaN());
    const volume::PackedVoxel* own = leaf.buffer().data();
    for (int x = 0; x < kLeafDim; ++x)
      for (int y = 0; y < kLeafDim; ++y) {
        float* row = &at(x, y, 0);
        const volume::PackedVoxel* from = own + ((x << 6) | (y << 3));
        for (int z = 0; z < kLeafDim; ++z) row[z] = tsdfOrNaN(from[z]);
      }
    const openvdb::Coord origin = leaf.origin();
    for (int axis = 0; axis < 3; ++axis)
      for (int side : {-1, 1}) {
        openvdb::Coord neighbour_origin = origin;
        neighbour_origin[axis] += side * kLeafDim;
        const GeometryLeaf* neighbour = tree.probeConstLeaf(neighbour_origin);
        if (!neighbour) continue;
        const volume::PackedVoxel* values = neighbour->buffer().data();
        const int from = side < 0 ? kLeafDim - 1 : 0;  // the neighbour's layer that touches this leaf
        const int to = side < 0 ? -1 : kLeafDim;
        for (int a = 0; a < kLeafDim; ++a)
          for (int b = 0; b < kLeafDim; ++b) {
            std::array<int, 3> src{}, dst{};
            src[axis] = from;
            dst[axis] = to;
            src[(axis + 1) % 3] = dst[(axis + 1) % 3] = a;
            src[(axis + 2) % 3] = dst[(axis + 2) % 3] = b;
            at(dst[0], dst[1], dst[2]) = tsdfOrNaN(values[(src[0] << 6) | (src[1] << 3) | src[2]]);
          }
      }
  }
  // Local coordinates from -1 to kLeafDim.
  float operator()(int x, int y, int z) const { return values_[index(x, y, z)]; }
  // Steps between neighbours along x, y, z.
  static constexpr int kStride[3] = {kSide * kSide, kSide, 1};
  static int index(int x, int y, int z) { return (z + 1) + kSide * ((y + 1) + kSide * (x + 1)); }
  float at(int i) const { return values_[i]; }

 private:
  float& at(int x, int y, int z) { return values_[index(x, y, z)]; }
  std::array<float, kSide * kSide * kSide> values_;
};

CountedLabels::CountedLabels(const LabelLegend& legend) : counted_(std::size_t{1} << 16, 1) {
  counted_[kUnlabeled] = 0;
  for (LabelId id : legend.background_ids) counted_[id] = 0;
}

LeafScanner::LeafScanner(const volume::LabeledVolume& volume, const CountedLabels& counted, int min_instance_evidence)
    : tree_(volume.geometryGrid().tree()),
      instances_(volume.instanceGrid() ? &volume.instanceGrid()->tree() : nullptr),
      counted_(counted),
      min_instance_evidence_(min_instance_evidence),
      face_area_(static_cast<float>(volume.voxelSize() * volume.voxelSize())),
      brick_(std::make_unique<Brick>()) {}

LeafScanner::~LeafScanner() = default;

void LeafScanner::scan(const GeometryLeaf& leaf, std::vector<SurfaceVoxel>& out) {
  const volume::PackedVoxel* values = leaf.buffer().data();
  bool loaded = false;
  Brick& brick = *brick_;
  const auto* instance_leaf = instances_ ? instances_->probeConstLeaf(leaf.origin()) : nullptr;
  for (auto it = leaf.getValueMask().beginOn(); it; ++it) {
    const openvdb::Index n = it.pos();
    const volume::PackedVoxel packed = values[n];
    const LabelId label = volume::unpackLabel(packed);
    if (!counted_(label) || !volume::isObserved(packed)) continue;
    if (!loaded) {
      brick.load(tree_, leaf);
      loaded = true;
    }
    const int x = int(n >> 6), y = int((n >> 3) & 7), z = int(n & 7);
    const int centre = Brick::index(x, y, z);
    const float t = brick.at(centre);
    std::array<float, 3> minus{}, plus{};
    std::array<int, 3> owned{};
    int owned_total = 0;
    for (int axis = 0; axis < 3; ++axis) {
      minus[axis] = brick.at(centre - Brick::kStride[axis]);
      plus[axis] = brick.at(centre + Brick::kStride[axis]);
      owned[axis] = ownedCrossings(t, minus[axis], plus[axis]);
      owned_total += owned[axis];
    }
    if (owned_total == 0) continue;
    Eigen::Vector3f gradient(derivative(minus[0], t, plus[0]), derivative(minus[1], t, plus[1]),
                             derivative(minus[2], t, plus[2]));
    SurfaceVoxel voxel;
    voxel.ijk = leaf.offsetToGlobalCoord(n);
    const float norm = gradient.norm();
    if (norm > 0.0f) voxel.normal = gradient / norm;
    for (int axis = 0; axis < 3; ++axis)
      // Without a gradient, a crossing counts as the mean over orientations (1/sqrt(3)).
      voxel.area_m2 += owned[axis] * face_area_ * (norm > 0.0f ? std::abs(voxel.normal[axis]) : 0.57735f);
    voxel.label = label;
    voxel.score = volume::unpackScore(packed);
    if (instance_leaf) {
      const volume::PackedInstance evidence = instance_leaf->getValue(n);
      if (static_cast<int>(volume::instanceEvidenceOf(evidence)) >= min_instance_evidence_)
        voxel.instance = volume::instanceIdOf(evidence);
    }
    out.push_back(voxel);
  }
}

}  // namespace semfuse::objects::detail
