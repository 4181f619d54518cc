// The client's reading of the server's mesh PLY into arrays (client/src/mesh_arrays.cpp): the
// bytes the server's writer (render::plyBytes) produces come back as the mesh it wrote, and
// files that lie about their sizes, index past the vertices or are cut short are refused.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/client/mesh_arrays.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/render/ply_writer.hpp"

namespace semfuse::client {
namespace {

// Two triangles over four vertices, with labels 3 and 5 and distinct scores.
render::LabeledMesh twoTriangles() {
  render::LabeledMesh mesh;
  mesh.vertices = {{0.F, 0.F, 1.F}, {1.F, 0.F, 1.F}, {0.F, 1.F, 1.5F}, {1.F, 1.F, -2.25F}};
  mesh.normals = {{0.F, 0.F, -1.F}, {0.F, 0.F, -1.F}, {0.F, 1.F, 0.F}, {1.F, 0.F, 0.F}};
  mesh.labels = {3, 3, 5, 5};
  mesh.scores = {0.5F, 1.F, 2.F, 16.F};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  return mesh;
}

std::vector<uint8_t> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

std::vector<uint8_t> serverPly(const render::LabeledMesh& mesh, bool normals = true) {
  const LabelLegend legend = *builtinLegend("synthetic");
  render::PlyOptions options;
  options.normals = normals;
  auto ply = render::plyBytes(mesh, legend, options);
  EXPECT_TRUE(ply.ok()) << ply.error();
  return bytesOf(ply.value());
}

TEST(MeshArrays, TheServersPlyComesBackAsTheMeshItWrote) {
  const render::LabeledMesh mesh = twoTriangles();
  auto arrays = parseMeshPly(serverPly(mesh));
  ASSERT_TRUE(arrays.ok()) << arrays.error();
  const MeshArrays& a = arrays.value();
  ASSERT_EQ(a.vertexCount(), 4u);
  ASSERT_EQ(a.faceCount(), 2u);
  for (std::size_t v = 0; v < 4; ++v) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(a.positions[3 * v + c], mesh.vertices[v][c]);
      EXPECT_EQ(a.normals[3 * v + c], mesh.normals[v][c]);
    }
    EXPECT_EQ(a.labels[v], mesh.labels[v]);
    EXPECT_EQ(a.scores[v], mesh.scores[v]);
    const auto rgb = builtinLegend("synthetic")->colorOf(mesh.labels[v]);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(a.colors[3 * v + c], rgb[c]);
  }
  EXPECT_EQ(a.faces, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
}

TEST(MeshArrays, NormalsAreOptionalAndAnEmptyMeshIsAMesh) {
  auto without = parseMeshPly(serverPly(twoTriangles(), false));
  ASSERT_TRUE(without.ok()) << without.error();
  EXPECT_TRUE(without.value().normals.empty());
  EXPECT_EQ(without.value().labels.size(), 4u);

  auto empty = parseMeshPly(serverPly(render::LabeledMesh{}));
  ASSERT_TRUE(empty.ok()) << empty.error();
  EXPECT_EQ(empty.value().vertexCount(), 0u);
  EXPECT_EQ(empty.value().faceCount(), 0u);
}

std::string errorOf(const std::vector<uint8_t>& ply) {
  auto arrays = parseMeshPly(ply);
  EXPECT_FALSE(arrays.ok());
  if (arrays.ok()) return "";
  EXPECT_EQ(arrays.errorCode(), ErrorCode::kInvalidArgument);
  return arrays.error();
}

TEST(MeshArrays, CountsThatClaimMoreThanTheBytesAreRefusedBeforeAllocating) {
  const std::vector<uint8_t> original = serverPly(twoTriangles());
  std::string ply(original.begin(), original.end());
  const std::string huge = "element vertex 4000000000\n";
  ply.replace(ply.find("element vertex 4\n"), std::string("element vertex 4\n").size(), huge);
  EXPECT_NE(errorOf(bytesOf(ply)).find("4000000000 vertices"), std::string::npos);

  std::string faces(original.begin(), original.end());
  faces.replace(faces.find("element face 2\n"), std::string("element face 2\n").size(), "element face 3000000000\n");
  EXPECT_NE(errorOf(bytesOf(faces)).find("3000000000 faces"), std::string::npos);
}

TEST(MeshArrays, AFaceThatIndexesPastTheVerticesIsRefused) {
  std::vector<uint8_t> ply = serverPly(twoTriangles());
  // The last index of the last face (little-endian int32 2) becomes 4: one past the vertices.
  ply[ply.size() - 4] = 4;
  EXPECT_NE(errorOf(ply).find("face 1 indexes vertex 4 of 4"), std::string::npos) << errorOf(ply);
}

TEST(MeshArrays, TruncatedTrailingOrForeignFilesAreRefused) {
  std::vector<uint8_t> ply = serverPly(twoTriangles());
  std::vector<uint8_t> cut(ply.begin(), ply.end() - 1);
  EXPECT_NE(errorOf(cut).find("face"), std::string::npos) << errorOf(cut);
  std::vector<uint8_t> longer = ply;
  longer.push_back(0);
  EXPECT_NE(errorOf(longer).find("1 bytes after the last element"), std::string::npos) << errorOf(longer);

  EXPECT_NE(errorOf(bytesOf("solid cube\n")).find("does not start with 'ply'"), std::string::npos);
  EXPECT_NE(errorOf(bytesOf("ply\nformat ascii 1.0\nelement vertex 0\nend_header\n")).find("binary_little_endian"),
            std::string::npos);
  EXPECT_NE(errorOf(bytesOf("ply\nformat binary_little_endian 1.0\nelement vertex 1\n")).find("no end_header"),
            std::string::npos);
  EXPECT_NE(errorOf(bytesOf("ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\n"
                            "property float y\nend_header\n"))
                .find("x, y and z"),
            std::string::npos);
}

TEST(MeshArrays, OnlyTrianglesAreRead) {
  std::string ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  std::vector<uint8_t> bytes = bytesOf(ply);
  bytes.resize(bytes.size() + 4 * 12, 0);
  bytes.push_back(4);  // a quad
  for (int i = 0; i < 4; ++i) bytes.insert(bytes.end(), {static_cast<uint8_t>(i), 0, 0, 0});
  EXPECT_NE(errorOf(bytes).find("face 0 has 4 corners"), std::string::npos) << errorOf(bytes);
}

}  // namespace
}  // namespace semfuse::client
