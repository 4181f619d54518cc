// The live mesh on the wire: a MapUpdate and the map_blocks service through their codecs and the
// CDR bytes and back, what the decoders refuse, and the ROS 2 markers and cloud made of blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/map_update_codecs.hpp"
#include "semfuse/wire/ros_visualization.hpp"

namespace semfuse::wire {
namespace {

template <class Wire>
dds::Sample<Wire> overTheWire(const Wire& msg) {
  auto received = dds::deserialize<Wire>(dds::serialize(msg));
  if (!received.ok()) ADD_FAILURE() << received.error();
  return received.ok() ? std::move(received).value() : dds::Sample<Wire>();
}

// Two triangles over four vertices, the last one repeated from the block above.
MeshBlock squareBlock(BlockOrigin origin, bool with_colors = true) {
  MeshBlock b;
  b.origin = origin;
  b.revision = 41;
  b.own_vertices = 3;
  b.positions = {0, 0, 4096, 4096 * 8, 0, 4096, 4096 * 8, 4096 * 8, 4096, 2048, 36864, 4096};
  b.normals = {0, 0, 127, 0, 0, 127, 0, 0, 127, 0, -90, 90};
  b.labels = {4, 4, 5, 0};
  b.scores = {1.5F, 2.0F, 16.0F, -0.25F};
  if (with_colors) b.colors = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30};
  b.triangles = {0, 1, 2, 0, 2, 3};
  return b;
}

void expectSameBlock(const MeshBlock& a, const MeshBlock& b) {
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.revision, b.revision);
  EXPECT_TRUE(a.sameMesh(b));
}

TEST(MapUpdateCodec, UpdateRoundTrip) {
  MapUpdate in;
  in.header = {0xFEEDFACECAFEBEEFull, 1234, 17, 1000, 0.01};
  in.previous_revision = 1200;
  in.part = 1;
  in.parts = 3;
  in.stamp = {1700000000, 5};
  in.blocks = {squareBlock({-8, 16, 0}), squareBlock({0, 0, 8}, false), MeshBlock{}};
  in.blocks[2].origin = {24, 24, 24};  // a block whose surface went away
  in.blocks[2].revision = 1234;

  const EncodedMapUpdate encoded = encodeMapUpdate(in);
  auto out = decodeMapUpdate(*overTheWire(encoded.msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  const MapUpdate& u = out.value();
  EXPECT_EQ(u.header.session, in.header.session);
  EXPECT_EQ(u.header.revision, 1234u);
  EXPECT_EQ(u.header.cleared_revision, 17u);
  EXPECT_EQ(u.header.frames_integrated, 1000u);
  EXPECT_EQ(u.header.voxel_size, 0.01);
  EXPECT_EQ(u.previous_revision, 1200u);
  EXPECT_EQ(u.part, 1u);
  EXPECT_EQ(u.parts, 3u);
  EXPECT_EQ(u.stamp.sec, 1700000000);
  ASSERT_EQ(u.blocks.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) expectSameBlock(u.blocks[i], in.blocks[i]);
  EXPECT_TRUE(u.blocks[2].empty());
  // The encoded message points into the update's arrays rather than copying them.
  EXPECT_EQ(static_cast<const void*>(encoded.msg().blocks._buffer[0].positions._buffer),
            static_cast<const void*>(in.blocks[0].positions.data()));
}

TEST(MapUpdateCodec, VertexPositionsInTheWorld) {
  const MeshBlock b = squareBlock({-8, 16, 0});
  // (origin + position / 4096) * voxel: vertex 1 is 8 voxels along x from the origin, 1 up.
  const Eigen::Vector3f p = b.position(1, 0.02);
  EXPECT_FLOAT_EQ(p.x(), 0.0F);
  EXPECT_FLOAT_EQ(p.y(), 16 * 0.02F);
  EXPECT_FLOAT_EQ(p.z(), 0.02F);
  EXPECT_FLOAT_EQ(b.position(3, 0.02).y(), (16 + 9) * 0.02F);
  EXPECT_EQ(b.payloadBytes(), 24u + 12 + 8 + 16 + 12 + 12);
}

TEST(MapUpdateCodec, MapBlocksRequestAndPageRoundTrip) {
  MapBlocksRequest request;
  request.since_revision = 99;
  request.resume_after = BlockOrigin{-16, 8, 1024};
  request.max_bytes = 65536;
  dds::Sample<MapBlocksCodec::WireRequest> wire_request;
  MapBlocksCodec::encodeRequest(request, *wire_request);
  auto back = MapBlocksCodec::decodeRequest(*overTheWire(*wire_request));
  ASSERT_TRUE(back.ok()) << back.error();
  EXPECT_EQ(back.value().since_revision, 99u);
  ASSERT_TRUE(back.value().resume_after.has_value());
  EXPECT_EQ(*back.value().resume_after, (BlockOrigin{-16, 8, 1024}));
  EXPECT_EQ(back.value().max_bytes, 65536u);
  MapBlocksCodec::encodeRequest(MapBlocksRequest{}, *wire_request);
  EXPECT_FALSE(MapBlocksCodec::decodeRequest(*overTheWire(*wire_request)).value().resume_after.has_value());

  ServiceReply<MapBlocksPage> reply;
  reply.value.header = {7, 500, 3, 250, 0.01};
  reply.value.blocks = {squareBlock({0, 0, 0}), squareBlock({8, 0, 0})};
  reply.value.complete = false;
  reply.value.next_after = {8, 0, 0};
  dds::Sample<MapBlocksCodec::WireReply> wire_reply;
  MapBlocksCodec::encodeReply(reply, *wire_reply);
  auto page = MapBlocksCodec::decodeReply(*overTheWire(*wire_reply));
  ASSERT_TRUE(page.ok()) << page.error();
  EXPECT_TRUE(page.value().ok());
  EXPECT_EQ(page.value().value.header.revision, 500u);
  EXPECT_EQ(page.value().value.header.frames_integrated, 250u);
  EXPECT_FALSE(page.value().value.complete);
  EXPECT_EQ(page.value().value.next_after, (BlockOrigin{8, 0, 0}));
  ASSERT_EQ(page.value().value.blocks.size(), 2u);
  expectSameBlock(page.value().value.blocks[1], reply.value.blocks[1]);

  // A refusal keeps its code and message.
  MapBlocksCodec::encodeReply(ServiceReply<MapBlocksPage>::failure(ReplyCode::kUnavailable, "no live mesh"),
                              *wire_reply);
  auto refused = MapBlocksCodec::decodeReply(*overTheWire(*wire_reply));
  ASSERT_TRUE(refused.ok());
  EXPECT_EQ(refused.value().code, ReplyCode::kUnavailable);
  EXPECT_EQ(refused.value().message, "no live mesh");
}

// Each way a block can fail to add up, refused with a message that names it.
TEST(MapUpdateCodec, BlocksThatDoNotAddUpAreRefused) {
  struct Case {
    const char* what;
    void (*spoil)(MeshBlock&);
    const char* message;
  };
  const Case cases[] = {
      {"origin", [](MeshBlock& b) { b.origin[1] = 3; }, "origin is not a multiple of 8"},
      {"positions", [](MeshBlock& b) { b.positions.pop_back(); }, "positions has 11 values for 4 vertices"},
      {"normals", [](MeshBlock& b) { b.normals.push_back(0); }, "normals has 13 values"},
      {"scores", [](MeshBlock& b) { b.scores.pop_back(); }, "scores has 3 values"},
      {"score", [](MeshBlock& b) { b.scores[2] = std::nanf(""); }, "vertex 2 has a score that is not a finite number"},
      {"colors", [](MeshBlock& b) { b.colors.resize(6); }, "colors has 6 values"},
      {"own", [](MeshBlock& b) { b.own_vertices = 5; }, "5 own vertices of 4"},
      {"triangle count", [](MeshBlock& b) { b.triangles.pop_back(); }, "not a multiple of 3"},
      {"triangle index", [](MeshBlock& b) { b.triangles[4] = 4; }, "triangle 1 names vertex 4 of 4"},
  };
  for (const Case& c : cases) {
    MeshBlock block = squareBlock({0, 8, 16});
    c.spoil(block);
    const Status s = validateMeshBlock(block);
    ASSERT_FALSE(s.ok()) << c.what;
    const std::string name = "mesh block (0, " + std::to_string(block.origin[1]) + ", 16)";
    EXPECT_NE(s.error().find(name), std::string::npos) << s.error();
    EXPECT_NE(s.error().find(c.message), std::string::npos) << c.what << ": " << s.error();

    // The same block in an update: the decoder refuses the update, naming the block.
    MapUpdate update;
    update.header.voxel_size = 0.01;
    update.blocks = {squareBlock({0, 0, 0}), block};
    const EncodedMapUpdate encoded = encodeMapUpdate(update);
    auto decoded = decodeMapUpdate(*overTheWire(encoded.msg()));
    ASSERT_FALSE(decoded.ok()) << c.what;
    EXPECT_NE(decoded.error().find("block 1: " + name), std::string::npos) << decoded.error();
  }
  EXPECT_TRUE(validateMeshBlock(squareBlock({0, 8, 16})).ok());
}

TEST(MapUpdateCodec, UpdateHeadersThatMakeNoSenseAreRefused) {
  MapUpdate update;
  update.header.voxel_size = 0.01;
  update.part = 2;
  update.parts = 2;
  auto decoded = decodeMapUpdate(*overTheWire(encodeMapUpdate(update).msg()));
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("part 2 of 2"), std::string::npos) << decoded.error();
  update.part = 0;
  update.header.voxel_size = 0.0;
  decoded = decodeMapUpdate(*overTheWire(encodeMapUpdate(update).msg()));
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("voxel size"), std::string::npos) << decoded.error();
}

LabelLegend testLegend() {
  LabelLegend legend;
  legend.name = "test";
  legend.labels = {{0, "unlabeled", {0, 0, 0}}, {4, "table", {230, 150, 30}}, {5, "chair", {220, 40, 60}}};
  return legend;
}

TEST(RosVisualization, BlockMarkerIsATriangleListWithCornerColours) {
  const MeshBlock block = squareBlock({-8, 16, 0});
  VisualizationStyle style;
  style.frame_id = "map";
  style.stamp = {12, 34};
  dds::Sample<visualization_msgs_msg_dds__Marker_> marker;
  fillBlockMarker(*marker, block, 7, 0.02, testLegend(), style);
  auto received = overTheWire(*marker);
  const auto& m = *received;
  EXPECT_STREQ(m.header.frame_id, "map");
  EXPECT_EQ(m.header.stamp.sec, 12);
  EXPECT_STREQ(m.ns, "semfuse_map");
  EXPECT_EQ(m.id, 7);
  EXPECT_EQ(m.type, visualization_msgs_msg_dds__Marker_Constants_TRIANGLE_LIST);
  EXPECT_EQ(m.action, visualization_msgs_msg_dds__Marker_Constants_ADD);
  EXPECT_EQ(m.pose.orientation.w, 1.0);
  EXPECT_EQ(m.scale.x, 1.0);
  EXPECT_EQ(m.color.a, 1.0F);
  // Three points per triangle, at the vertices' world positions, coloured by label.
  ASSERT_EQ(m.points._length, 6u);
  ASSERT_EQ(m.colors._length, 6u);
  const uint16_t corners[6] = {0, 1, 2, 0, 2, 3};
  for (int c = 0; c < 6; ++c) {
    const Eigen::Vector3f p = block.position(corners[c], 0.02);
    EXPECT_FLOAT_EQ(static_cast<float>(m.points._buffer[c].x), p.x());
    EXPECT_FLOAT_EQ(static_cast<float>(m.points._buffer[c].z), p.z());
    EXPECT_EQ(m.colors._buffer[c].a, 1.0F);
  }
  EXPECT_FLOAT_EQ(m.colors._buffer[0].r, 230 / 255.0F);  // table
  EXPECT_FLOAT_EQ(m.colors._buffer[2].g, 40 / 255.0F);   // chair
  // Vertex 3 is unlabeled: its RGB.
  EXPECT_FLOAT_EQ(m.colors._buffer[5].b, 30 / 255.0F);

  // RGB colouring, and a block without surface is deleted.
  style.coloring = VertexColoring::kRgb;
  fillBlockMarker(*marker, block, 7, 0.02, testLegend(), style);
  EXPECT_FLOAT_EQ(marker->colors._buffer[0].r, 1.0F);
  MeshBlock gone;
  gone.origin = block.origin;
  fillBlockMarker(*marker, gone, 7, 0.02, testLegend(), style);
  EXPECT_EQ(overTheWire(*marker)->action, visualization_msgs_msg_dds__Marker_Constants_DELETE);
  fillDeleteAllMarker(*marker, style);
  EXPECT_EQ(overTheWire(*marker)->action, visualization_msgs_msg_dds__Marker_Constants_DELETEALL);
}

TEST(RosVisualization, SurfaceCloudHasOnePointPerOwnVertex) {
  const MeshBlock a = squareBlock({0, 0, 0}), b = squareBlock({8, 0, 0}, false);
  dds::Sample<sensor_msgs_msg_dds__PointCloud2_> cloud;
  fillSurfaceCloud(*cloud, {&a, &b}, 0.01, testLegend(), VisualizationStyle{});
  auto received = overTheWire(*cloud);
  const auto& c = *received;
  EXPECT_EQ(c.height, 1u);
  EXPECT_EQ(c.width, 6u);  // 3 own vertices each; the repeated ones are left out
  EXPECT_EQ(c.point_step, kSurfacePointStep);
  EXPECT_EQ(c.row_step, 6 * kSurfacePointStep);
  EXPECT_TRUE(c.is_dense);
  EXPECT_FALSE(c.is_bigendian);
  ASSERT_EQ(c.fields._length, 6u);
  const char* names[6] = {"x", "y", "z", "rgb", "label", "confidence"};
  const uint32_t offsets[6] = {0, 4, 8, 12, 16, 20};
  for (int f = 0; f < 6; ++f) {
    EXPECT_STREQ(c.fields._buffer[f].name, names[f]);
    EXPECT_EQ(c.fields._buffer[f].offset, offsets[f]);
    EXPECT_EQ(c.fields._buffer[f].count, 1u);
  }
  EXPECT_EQ(c.fields._buffer[4].datatype, point_field::kUint32);
  EXPECT_EQ(c.fields._buffer[3].datatype, point_field::kFloat32);
  ASSERT_EQ(c.data._length, 6 * kSurfacePointStep);
  // Point 4: block b's vertex 1, label 4 (table), score 2.
  const uint8_t* point = c.data._buffer + 4 * kSurfacePointStep;
  float xyz[3], confidence;
  uint32_t rgb, label;
  std::memcpy(xyz, point, 12);
  std::memcpy(&rgb, point + 12, 4);
  std::memcpy(&label, point + 16, 4);
  std::memcpy(&confidence, point + 20, 4);
  EXPECT_FLOAT_EQ(xyz[0], 0.16F);
  EXPECT_FLOAT_EQ(xyz[2], 0.01F);
  EXPECT_EQ(rgb, (230u << 16) | (150u << 8) | 30u);
  EXPECT_EQ(label, 4u);
  EXPECT_EQ(confidence, 2.0F);
}

}  // namespace
}  // namespace semfuse::wire
