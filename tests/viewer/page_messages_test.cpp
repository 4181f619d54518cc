// What semfuse-viewer sends the page: the binary block layout viewer.js reads (world positions of
// a known block, scores, indices, labels padded to 4 bytes, RGB), removals and clears, and JSON
// that stays valid whatever the names hold.
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "page_messages.hpp"

namespace semfuse::viewer {
namespace {

template <class T>
T at(const std::string& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

MeshBlock triangleBlock() {
  MeshBlock block;
  block.origin = {8, -16, 0};
  block.revision = 3;
  block.own_vertices = 2;
  // Vertex 1 at half a voxel along x, vertex 2 at two voxels along z.
  block.positions = {0, 0, 0, 2048, 0, 0, 0, 0, 8192};
  block.normals = {0, 0, 127, 0, 0, 127, 0, 0, 127};
  block.labels = {4, 5, 6};
  block.scores = {1.5F, 2.5F, 3.5F};
  block.colors = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  block.triangles = {0, 1, 2};
  return block;
}

TEST(PageMessages, ABlockCarriesWorldPositionsAndItsArraysWhereThePageReadsThem) {
  const std::string m = blockMessage(triangleBlock(), 0.1);
  // Header 28 bytes; positions 36, scores 12, indices 12, labels 6 + 2 padding, RGB 9.
  ASSERT_EQ(m.size(), 28u + 36 + 12 + 12 + 8 + 9);
  EXPECT_EQ(at<uint32_t>(m, 0), static_cast<uint32_t>(BlockMessage::kBlock));
  EXPECT_EQ(at<int32_t>(m, 4), 8);
  EXPECT_EQ(at<int32_t>(m, 8), -16);
  EXPECT_EQ(at<uint32_t>(m, 16), 3u);  // vertices
  EXPECT_EQ(at<uint32_t>(m, 20), 1u);  // triangles
  EXPECT_EQ(at<uint32_t>(m, 24), 2u);  // own vertices
  // Vertex 0 at the origin (0.8, -1.6, 0) m; vertex 1 half a voxel further along x.
  EXPECT_FLOAT_EQ(at<float>(m, 28), 0.8F);
  EXPECT_FLOAT_EQ(at<float>(m, 32), -1.6F);
  EXPECT_FLOAT_EQ(at<float>(m, 28 + 12), 0.85F);
  EXPECT_FLOAT_EQ(at<float>(m, 28 + 24 + 8), 0.2F);  // vertex 2's z
  EXPECT_FLOAT_EQ(at<float>(m, 64 + 8), 3.5F);       // score of vertex 2
  EXPECT_EQ(at<uint32_t>(m, 76 + 8), 2u);            // third index
  EXPECT_EQ(at<uint16_t>(m, 88 + 2), 5u);            // label of vertex 1
  EXPECT_EQ(static_cast<uint8_t>(m[96 + 8]), 9u);    // blue of vertex 2
}

TEST(PageMessages, ABlockWithoutColourSendsBlackAndRemovalsAndClearsAreShort) {
  MeshBlock block = triangleBlock();
  block.colors.clear();
  const std::string m = blockMessage(block, 0.1);
  ASSERT_EQ(m.size(), 28u + 36 + 12 + 12 + 8 + 9);
  for (std::size_t i = 96; i < m.size(); ++i) EXPECT_EQ(m[i], '\0');

  const std::string removed = removedMessage({8, 0, -8});
  ASSERT_EQ(removed.size(), 16u);
  EXPECT_EQ(at<uint32_t>(removed, 0), static_cast<uint32_t>(BlockMessage::kRemoved));
  EXPECT_EQ(at<int32_t>(removed, 12), -8);
  EXPECT_EQ(clearedMessage().size(), 4u);
}

TEST(PageMessages, JsonEscapesWhatNamesMayHoldAndWritesNoNaN) {
  EXPECT_EQ(jsonString("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
  EXPECT_EQ(jsonString("tab\there, caf\xc3\xa9"), "\"tab\\there, caf\xc3\xa9\"");  // UTF-8 passes through
  LabelLegend legend;
  legend.name = "quote\"d";
  legend.labels = {{3, "chair \"old\"", {1, 2, 3}}};
  legend.background_ids = {3};
  EXPECT_EQ(
      legendJson(legend),
      R"({"type":"legend","name":"quote\"d","labels":[{"id":3,"name":"chair \"old\"","rgb":[1,2,3],"background":true}]})");

  VoxelSample sample;
  sample.observed = true;
  sample.label = 9;  // not in the legend
  sample.confidence = std::numeric_limits<float>::quiet_NaN();
  const std::string answer = labelsAtJson({1, 2, 3}, sample, legend);
  EXPECT_NE(answer.find(R"("name":"label 9")"), std::string::npos) << answer;
  EXPECT_NE(answer.find(R"("confidence":null)"), std::string::npos) << answer;
  EXPECT_EQ(answer.find("nan"), std::string::npos) << answer;
}

TEST(PageMessages, PosesAreColumnMajorMatricesAsThreeJsTakesThem) {
  TrackedPose pose;
  pose.camera_id = "cam0";
  pose.seq = 7;
  pose.posed = true;
  pose.camera_to_world.translation() = Eigen::Vector3d(1.5, -2, 0.25);
  const std::string json = posesJson({pose});
  // Column-major: the translation is elements 12-14.
  EXPECT_NE(json.find(R"("m":[1,0,0,0,0,1,0,0,0,0,1,0,1.5,-2,0.25,1])"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("camera":"cam0","seq":7,"posed":true,"state":"given")"), std::string::npos) << json;
}

TEST(PageMessages, TheRaycastIsAPngOfLegendColoursBlackWhereNothingWasHit) {
  RaycastImages view;
  view.labels = (cv::Mat_<uint16_t>(1, 3) << 4, 4, 7);
  view.depth = (cv::Mat_<float>(1, 3) << 1.5F, 0.0F, 2.0F);
  LabelLegend legend;
  legend.labels = {{4, "table", {230, 150, 30}}, {7, "sphere", {145, 60, 200}}};
  const std::string m = raycastMessage(view, legend);
  ASSERT_GT(m.size(), 4u);
  EXPECT_EQ(at<uint32_t>(m, 0), static_cast<uint32_t>(BlockMessage::kRaycast));
  const std::vector<uint8_t> png(m.begin() + 4, m.end());
  const cv::Mat bgr = cv::imdecode(png, cv::IMREAD_COLOR);
  ASSERT_EQ(bgr.size(), cv::Size(3, 1));
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 0), cv::Vec3b(30, 150, 230));
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 1), cv::Vec3b(0, 0, 0));  // depth 0: no surface
  EXPECT_EQ(bgr.at<cv::Vec3b>(0, 2), cv::Vec3b(200, 60, 145));
}

}  // namespace
}  // namespace semfuse::viewer
