// The PLY bytes parse back: header, counts, a vertex and a face, as a reader would see them.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "semfuse/render/ply_writer.hpp"

namespace semfuse::render {
namespace {

LabeledMesh twoTriangles() {
  LabeledMesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
  m.normals.assign(4, Eigen::Vector3f(0, 0, 1));
  m.labels = {4, 4, 7, 0};
  m.scores = {1.5f, 2.0f, 0.25f, 0.0f};
  m.colors = {{10, 20, 30}, {40, 50, 60}, {70, 80, 90}, {1, 2, 3}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

template <class T>
T readAt(const std::string& bytes, size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof value);  // test host is little endian (x86-64)
  return value;
}

TEST(Ply, HeaderCountsAndRecordsReadBack) {
  const LabelLegend legend{"test", {{7, "sphere", {255, 0, 128}}}, {}};
  const auto bytes = plyBytes(twoTriangles(), legend);
  ASSERT_TRUE(bytes.ok()) << bytes.error();
  const std::string& ply = bytes.value();
  const size_t end = ply.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  const std::string header = ply.substr(0, end);
  EXPECT_EQ(header.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_NE(header.find("element vertex 4\n"), std::string::npos);
  EXPECT_NE(header.find("property ushort label\n"), std::string::npos);
  EXPECT_NE(header.find("element face 2\n"), std::string::npos);
  const size_t body = end + std::strlen("end_header\n");
  constexpr size_t kVertexBytes = 12 + 12 + 3 + 2 + 4;
  ASSERT_EQ(ply.size(), body + 4 * kVertexBytes + 2 * 13);
  // Vertex 2: position, normal, palette colour of label 7, label, score.
  const size_t v2 = body + 2 * kVertexBytes;
  EXPECT_EQ(readAt<float>(ply, v2), 1.0f);
  EXPECT_EQ(readAt<float>(ply, v2 + 4), 1.0f);
  EXPECT_EQ(readAt<float>(ply, v2 + 20), 1.0f);  // nz
  EXPECT_EQ(static_cast<uint8_t>(ply[v2 + 24]), 255);
  EXPECT_EQ(static_cast<uint8_t>(ply[v2 + 26]), 128);
  EXPECT_EQ(readAt<uint16_t>(ply, v2 + 27), 7);
  EXPECT_EQ(readAt<float>(ply, v2 + 29), 0.25f);
  // Face 1: count 3 then indices 0 2 3.
  const size_t f1 = body + 4 * kVertexBytes + 13;
  EXPECT_EQ(static_cast<uint8_t>(ply[f1]), 3);
  EXPECT_EQ(readAt<int32_t>(ply, f1 + 5), 2);
  EXPECT_EQ(readAt<int32_t>(ply, f1 + 9), 3);
}

TEST(Ply, VoxelColourAndNoNormals) {
  PlyOptions options;
  options.normals = false;
  options.color = PlyColor::kVoxelColor;
  const std::string ply = plyBytes(twoTriangles(), LabelLegend{}, options).value();
  EXPECT_EQ(ply.find("property float nx"), std::string::npos);
  const size_t body = ply.find("end_header\n") + std::strlen("end_header\n");
  const size_t v1 = body + (12 + 3 + 2 + 4);
  EXPECT_EQ(static_cast<uint8_t>(ply[v1 + 12]), 40);
  EXPECT_EQ(static_cast<uint8_t>(ply[v1 + 14]), 60);
}

TEST(Ply, InconsistentMeshIsAnError) {
  LabeledMesh bad_index = twoTriangles();
  bad_index.triangles.push_back({0, 1, 9});
  const auto a = plyBytes(bad_index, LabelLegend{});
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().find("indexes vertex 9"), std::string::npos) << a.error();
  LabeledMesh no_colors = twoTriangles();
  no_colors.colors.clear();
  PlyOptions voxel_color;
  voxel_color.color = PlyColor::kVoxelColor;
  EXPECT_FALSE(plyBytes(no_colors, LabelLegend{}, voxel_color).ok());
  EXPECT_TRUE(plyBytes(no_colors, LabelLegend{}).ok());
}

}  // namespace
}  // namespace semfuse::render
