#include "mesh_volume_to_mesh.hpp"

#include <openvdb/tools/Morphology.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "semfuse/volume/volume_sampler.hpp"

namespace semfuse::render::detail {
namespace {

using volume::GeometryGrid;
using GeometryTree = GeometryGrid::TreeType;
using FloatTree = GeometryTree::ValueConverter<float>::Type;
using BoolTree = GeometryTree::ValueConverter<bool>::Type;

// The TSDF as a FloatGrid with the volume's topology: what VolumeToMesh reads. Unobserved voxels
// get +truncation (free space); the surface mask below keeps them from producing surface anyway.
openvdb::FloatGrid::Ptr tsdfGrid(const volume::LabeledVolume& volume) {
  const auto truncation = static_cast<float>(volume.params().truncation);
  auto tree = std::make_shared<FloatTree>(volume.geometryGrid().tree(), truncation, openvdb::TopologyCopy());
  openvdb::tree::LeafManager<FloatTree> leaves(*tree);
  const GeometryTree& geometry = volume.geometryGrid().tree();
  leaves.foreach ([&](FloatTree::LeafNodeType& leaf, size_t) {
    const auto* source = geometry.probeConstLeaf(leaf.origin());
    if (!source) return;
    const volume::PackedVoxel* packed = source->buffer().data();
    float* values = leaf.buffer().data();
    for (openvdb::Index i = 0; i < FloatTree::LeafNodeType::SIZE; ++i)
      values[i] = volume::isObserved(packed[i]) ? volume::unpackTsdf(packed[i]) : truncation;
  });
  auto grid = openvdb::FloatGrid::create(tree);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(volume.voxelSize()));
  return grid;
}

// Cells VolumeToMesh may polygonise. Its quads join the vertices of the four cells around each
// sign-changing edge, so a cell may only take part when its whole 3x3x3 voxel neighbourhood was
// observed: eroding the observed set once with 26-neighbour connectivity gives exactly that.
// With bounds, voxels outside them are dropped too.
openvdb::BoolGrid::Ptr observedCellMask(const volume::LabeledVolume& volume,
                                        const std::optional<openvdb::CoordBBox>& bounds) {
  auto tree = std::make_shared<BoolTree>(volume.geometryGrid().tree(), false, openvdb::TopologyCopy());
  openvdb::tools::erodeActiveValues(*tree, 1, openvdb::tools::NN_FACE_EDGE_VERTEX, openvdb::tools::IGNORE_TILES);
  if (bounds) {
    openvdb::tree::LeafManager<BoolTree> leaves(*tree);
    leaves.foreach ([&](BoolTree::LeafNodeType& leaf, size_t) {
      for (auto it = leaf.beginValueOn(); it; ++it)
        if (!bounds->isInside(it.getCoord())) it.setValueOff();
    });
  }
  auto grid = openvdb::BoolGrid::create(tree);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(volume.voxelSize()));
  return grid;
}

void collectTriangles(const openvdb::tools::VolumeToMesh& mesher, LabeledMesh& mesh) {
  const openvdb::tools::PolygonPoolList& pools = mesher.polygonPoolList();
  size_t count = 0;
  for (size_t p = 0; p < mesher.polygonPoolListSize(); ++p) count += pools[p].numTriangles() + 2 * pools[p].numQuads();
  mesh.triangles.reserve(count);
  // VolumeToMesh already winds counter-clockwise seen from the positive (free) side, which is
  // what PLY viewers take as the front face.
  for (size_t p = 0; p < mesher.polygonPoolListSize(); ++p) {
    const openvdb::tools::PolygonPool& pool = pools[p];
    for (size_t i = 0; i < pool.numTriangles(); ++i) {
      const openvdb::Vec3I& t = pool.triangle(i);
      mesh.triangles.push_back({t[0], t[1], t[2]});
    }
    for (size_t i = 0; i < pool.numQuads(); ++i) {
      const openvdb::Vec4I& q = pool.quad(i);
      mesh.triangles.push_back({q[0], q[1], q[2]});
      mesh.triangles.push_back({q[0], q[2], q[3]});
    }
  }
}

// Normal, label, score and colour of every vertex, from the voxels around it.
void attributeVertices(const volume::LabeledVolume& volume, LabeledMesh& mesh) {
  const size_t n = mesh.vertices.size();
  mesh.normals.assign(n, Eigen::Vector3f::Zero());
  mesh.labels.assign(n, kUnlabeled);
  mesh.scores.assign(n, 0.0f);
  if (volume.hasColor()) mesh.colors.assign(n, volume::Rgb8{});
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    volume::VolumeSampler sampler(volume);
    for (size_t i = range.begin(); i < range.end(); ++i) {
      const Eigen::Vector3f& p = mesh.vertices[i];
      float f;
      Eigen::Vector3f gradient;
      if (sampler.tsdfAndGradient(p, f, gradient) && gradient.squaredNorm() > 0.0f)
        mesh.normals[i] = gradient.normalized();
      volume::VoxelValue voxel;
      if (sampler.nearestVoxel(p, voxel)) {
        mesh.labels[i] = voxel.label;
        mesh.scores[i] = voxel.score;
      }
      if (!mesh.colors.empty()) sampler.nearestColor(p, mesh.colors[i]);
    }
  });
}

}  // namespace

LabeledMesh volumeToMeshReference(const volume::LabeledVolume& volume,
                                  const std::optional<openvdb::CoordBBox>& cell_bounds) {
  LabeledMesh mesh;
  if (volume.geometryGrid().tree().leafCount() == 0) return mesh;
  const openvdb::FloatGrid::Ptr tsdf = tsdfGrid(volume);
  openvdb::tools::VolumeToMesh mesher(/*isovalue=*/0.0, /*adaptivity=*/0.0);
  mesher.setSurfaceMask(observedCellMask(volume, cell_bounds));
  mesher(*tsdf);

  const openvdb::tools::PointList& points = mesher.pointList();
  mesh.vertices.resize(mesher.pointListSize());
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    mesh.vertices[i] = Eigen::Vector3f(points[i].x(), points[i].y(), points[i].z());
  collectTriangles(mesher, mesh);
  attributeVertices(volume, mesh);
  return mesh;
}

}  // namespace semfuse::render::detail
