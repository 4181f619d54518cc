#include "map_layers.hpp"

#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/parallel_for.h>

namespace semfuse::volume::detail {
namespace {
using GeometryTree = GeometryGrid::TreeType;
using GeometryLeaf = GeometryTree::LeafNodeType;
constexpr openvdb::Index kLeafSize = GeometryLeaf::SIZE;

template <typename GridT>
typename GridT::Ptr layerLike(const LabeledVolume& volume, typename GridT::ValueType background, const char* name) {
  // TopologyCopy keeps every allocated leaf and its active mask, observed or not.
  auto tree =
      std::make_shared<typename GridT::TreeType>(volume.geometryGrid().tree(), background, openvdb::TopologyCopy());
  auto grid = GridT::create(tree);
  grid->setTransform(volume.geometryGrid().transform().copy());
  grid->setName(name);
  return grid;
}

template <typename T>
void hashBytes(uint64_t& hash, const T* data, std::size_t count) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < count * sizeof(T); ++i) {
    hash ^= bytes[i];
    hash *= 1099511628211ull;
  }
}
}  // namespace

MapLayers splitLayers(const LabeledVolume& volume) {
  const float truncation = static_cast<float>(volume.params().truncation);
  MapLayers layers;
  layers.tsdf = layerLike<openvdb::FloatGrid>(volume, truncation, "tsdf");
  layers.tsdf->setGridClass(openvdb::GRID_LEVEL_SET);
  layers.weight = layerLike<openvdb::FloatGrid>(volume, 0.0f, "weight");
  layers.score = layerLike<openvdb::FloatGrid>(volume, 0.0f, "score");
  layers.label = layerLike<openvdb::Int32Grid>(volume, 0, "label");
  // Every value is a half float in memory: saving as half loses nothing and halves the file.
  for (auto& grid : {layers.tsdf, layers.weight, layers.score}) grid->setSaveFloatAsHalf(true);

  std::vector<const GeometryLeaf*> leaves;
  volume.geometryGrid().tree().getNodes(leaves);
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    const GeometryLeaf& packed = *leaves[i];
    const openvdb::Coord origin = packed.origin();
    auto* tsdf = layers.tsdf->tree().probeLeaf(origin);
    auto* weight = layers.weight->tree().probeLeaf(origin);
    auto* score = layers.score->tree().probeLeaf(origin);
    auto* label = layers.label->tree().probeLeaf(origin);
    for (auto it = packed.cbeginValueOn(); it; ++it) {
      const openvdb::Index n = it.pos();
      const PackedVoxel v = *it;
      tsdf->setValueOnly(n, unpackTsdf(v));
      weight->setValueOnly(n, unpackWeight(v));
      score->setValueOnly(n, unpackScore(v));
      label->setValueOnly(n, unpackLabel(v));
    }
  });
  return layers;
}

Result<GeometryGrid::TreeType::Ptr> mergeLayers(const MapLayers& layers) {
  const auto& tsdf = layers.tsdf->tree();
  if (!tsdf.hasSameTopology(layers.weight->tree()) || !tsdf.hasSameTopology(layers.score->tree()) ||
      !tsdf.hasSameTopology(layers.label->tree()))
    return makeError("the tsdf, weight, score and label grids have different topologies");

  auto packed = std::make_shared<GeometryTree>(tsdf, kUnobservedVoxel, openvdb::TopologyCopy());
  std::vector<GeometryLeaf*> leaves;
  packed->getNodes(leaves);
  std::atomic<bool> bad_value{false};
  tbb::parallel_for(std::size_t{0}, leaves.size(), [&](std::size_t i) {
    GeometryLeaf& out = *leaves[i];
    const openvdb::Coord origin = out.origin();
    const auto* t = tsdf.probeConstLeaf(origin);
    const auto* w = layers.weight->tree().probeConstLeaf(origin);
    const auto* s = layers.score->tree().probeConstLeaf(origin);
    const auto* l = layers.label->tree().probeConstLeaf(origin);
    for (openvdb::Index n = 0; n < kLeafSize; ++n) {
      if (!out.isValueOn(n)) continue;
      const float weight = w->getValue(n);
      const int32_t label = l->getValue(n);
      if (!(weight > 0.0f) || !std::isfinite(weight) || !std::isfinite(t->getValue(n)) ||
          !std::isfinite(s->getValue(n)) || label < 0 || label > 65535) {
        bad_value = true;
        return;
      }
      out.setValueOnly(n, packVoxel(t->getValue(n), weight, static_cast<LabelId>(label), s->getValue(n)));
    }
  });
  if (bad_value)
    return makeError(
        "an observed voxel holds a value the volume cannot (weight <= 0, non-finite, or label "
        "outside 0..65535)");
  return packed;
}

uint64_t voxelChecksum(const GeometryGrid::TreeType& geometry, const ColorGrid::TreeType* color) {
  uint64_t hash = 14695981039346656037ull;
  for (auto leaf = geometry.cbeginLeaf(); leaf; ++leaf) {
    const openvdb::Coord origin = leaf->origin();
    hashBytes(hash, origin.data(), 3);
    for (openvdb::Index w = 0; w < GeometryLeaf::NodeMaskType::WORD_COUNT; ++w) {
      const auto word = leaf->getValueMask().getWord<openvdb::Index64>(w);
      hashBytes(hash, &word, 1);
    }
    hashBytes(hash, leaf->buffer().data(), kLeafSize);
    if (color) {
      if (const auto* c = color->probeConstLeaf(origin)) hashBytes(hash, c->buffer().data(), kLeafSize);
    }
  }
  return hash;
}

}  // namespace semfuse::volume::detail
