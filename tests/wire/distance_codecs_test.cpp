// The distance field's services and the nav_msgs/OccupancyGrid message over the wire and back:
// encode, the CDR bytes Cyclone sends, decode, field by field; then what the decoders refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "round_trip.hpp"
#include "semfuse/wire/distance_codecs.hpp"

namespace semfuse::wire {
namespace {

OccupancyGrid threeByTwo() {
  OccupancyGrid grid;
  grid.frame_id = "map";
  grid.stamp = {1700000000, 123};
  grid.resolution = 0.05;
  grid.width = 3;
  grid.height = 2;
  grid.origin = {-1.25, 2.5};
  grid.z = 0.375;
  grid.cells = {0, 100, -1, 99, 0, 0};
  return grid;
}

TEST(DistanceCodecs, RequestsRoundTrip) {
  const auto distance = requestRoundTrip<DistanceCodec>({{{1, 2, 3}, {-4.5, 0, 1e-9}}});
  ASSERT_EQ(distance.points.size(), 2u);
  EXPECT_EQ(distance.points[1], Eigen::Vector3d(-4.5, 0, 1e-9));

  OccupancySliceRequest slice;
  slice.z_min = 0.2;
  slice.z_max = 0.7;
  slice.use_bounds = true;
  slice.min = {-1, -2};
  slice.max = {3, 4};
  slice.inflation_radius = 0.3;
  const auto slice_back = requestRoundTrip<OccupancySliceCodec>(slice);
  EXPECT_EQ(slice_back.z_min, 0.2);
  EXPECT_EQ(slice_back.z_max, 0.7);
  EXPECT_TRUE(slice_back.use_bounds);
  EXPECT_EQ(slice_back.min, Eigen::Vector2d(-1, -2));
  EXPECT_EQ(slice_back.max, Eigen::Vector2d(3, 4));
  EXPECT_EQ(slice_back.inflation_radius, 0.3);

  const auto semantic = requestRoundTrip<SemanticDistanceCodec>({{4, 65535}, {{0.5, 0.25, 1}}});
  EXPECT_EQ(semantic.labels, (std::vector<LabelId>{4, 65535}));
  EXPECT_EQ(semantic.points[0], Eigen::Vector3d(0.5, 0.25, 1));

  const auto semantic_slice = requestRoundTrip<SemanticSliceCodec>({{7}, 1.25, {-1, -1}, {2, 3}, 0.1});
  EXPECT_EQ(semantic_slice.labels, std::vector<LabelId>{7});
  EXPECT_EQ(semantic_slice.z, 1.25);
  EXPECT_EQ(semantic_slice.max, Eigen::Vector2d(2, 3));
  EXPECT_EQ(semantic_slice.resolution, 0.1);

  const auto segments = requestRoundTrip<SegmentCheckCodec>({{{{0, 0, 0}, {1, 2, 3}}, {{4, 5, 6}, {7, 8, 9}}}, 0.2});
  ASSERT_EQ(segments.segments.size(), 2u);
  EXPECT_EQ(segments.segments[1].end, Eigen::Vector3d(7, 8, 9));
  EXPECT_EQ(segments.radius, 0.2);
}

TEST(DistanceCodecs, RepliesRoundTrip) {
  const auto distance = replyValueRoundTrip<DistanceCodec>(
      {{true, false, -0.03f, {0, 0, 1}}, {false, true, 2.0f, Eigen::Vector3f::Zero()}});
  ASSERT_EQ(distance.value.size(), 2u);
  EXPECT_TRUE(distance.value[0].known);
  EXPECT_FLOAT_EQ(distance.value[0].distance, -0.03f);
  EXPECT_EQ(distance.value[0].gradient, Eigen::Vector3f(0, 0, 1));
  EXPECT_TRUE(distance.value[1].beyond);

  const auto grid = replyValueRoundTrip<OccupancySliceCodec>(threeByTwo()).value;
  EXPECT_EQ(grid.frame_id, "map");
  EXPECT_EQ(grid.stamp.sec, 1700000000);
  EXPECT_FLOAT_EQ(static_cast<float>(grid.resolution), 0.05f);
  EXPECT_EQ(grid.width, 3u);
  EXPECT_EQ(grid.height, 2u);
  EXPECT_EQ(grid.origin, Eigen::Vector2d(-1.25, 2.5));
  EXPECT_EQ(grid.z, 0.375);
  EXPECT_EQ(grid.cells, threeByTwo().cells);

  const auto semantic = replyValueRoundTrip<SemanticDistanceCodec>(
      {{true, 4, 0.5f, {0, 0, -1}, {0.2, 0.1, 0.75}}, {false, 0, 0, Eigen::Vector3f::Zero(), Eigen::Vector3d::Zero()}});
  ASSERT_EQ(semantic.value.size(), 2u);
  EXPECT_EQ(semantic.value[0].label, 4);
  EXPECT_EQ(semantic.value[0].surface_point, Eigen::Vector3d(0.2, 0.1, 0.75));
  EXPECT_FALSE(semantic.value[1].found);

  cv::Mat distances(2, 3, CV_32FC1);
  distances.at<float>(1, 2) = std::numeric_limits<float>::infinity();
  distances.at<float>(0, 0) = 0.25f;
  const auto slice = replyValueRoundTrip<SemanticSliceCodec>({{-1, -2}, 0.1, 1.25, distances}).value;
  EXPECT_EQ(slice.min, Eigen::Vector2d(-1, -2));
  EXPECT_EQ(slice.resolution, 0.1);
  ASSERT_EQ(slice.distance.type(), CV_32FC1);
  EXPECT_EQ(slice.distance.at<float>(0, 0), 0.25f);
  EXPECT_TRUE(std::isinf(slice.distance.at<float>(1, 2)));

  const auto segments =
      replyValueRoundTrip<SegmentCheckCodec>({{SegmentStatus::kCollision, 0.4f, {1, 2, 3}, -0.1f},
                                              {SegmentStatus::kUnknown, 0.0f, Eigen::Vector3d::Zero(), 0.0f}});
  ASSERT_EQ(segments.value.size(), 2u);
  EXPECT_EQ(segments.value[0].status, SegmentStatus::kCollision);
  EXPECT_EQ(segments.value[0].blocked_at, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(segments.value[1].status, SegmentStatus::kUnknown);
}

TEST(DistanceCodecs, MalformedGridsAndRepliesAreRefused) {
  auto refused = [](OccupancyGrid grid, const std::string& words, auto&& corrupt) {
    dds::Sample<nav_msgs_msg_dds__OccupancyGrid_> msg;
    fillOccupancyGrid(*msg, grid);
    corrupt(*msg);
    auto decoded = decodeOccupancyGrid(*overTheWire(*msg));
    ASSERT_FALSE(decoded.ok());
    EXPECT_NE(decoded.error().find(words), std::string::npos) << decoded.error();
  };
  refused(threeByTwo(), "holds 6 cells, 4x2 declared", [](auto& m) { m.info.width = 4; });
  refused(threeByTwo(), "resolution", [](auto& m) { m.info.resolution = 0.0f; });
  refused(threeByTwo(), "resolution", [](auto& m) { m.info.resolution = std::nanf(""); });
  refused(threeByTwo(), "rotated", [](auto& m) { m.info.origin.orientation = {0, 0, 0.7071, 0.7071}; });
  refused(threeByTwo(), "sides above 65536", [](auto& m) { m.info.width = 70000; });
  OccupancyGrid bad = threeByTwo();
  bad.cells[1] = 101;
  refused(bad, "cell 1 holds 101", [](auto&) {});

  dds::Sample<semfuse_srv_dds__SegmentCheck_Response_> reply;
  SegmentCheckCodec::encodeReply({ReplyCode::kOk, "", {{SegmentStatus::kFree, 1.0f, Eigen::Vector3d::Zero(), 0.5f}}},
                                 *reply);
  reply->results._buffer[0].status = 7;
  auto decoded = SegmentCheckCodec::decodeReply(*reply);
  ASSERT_FALSE(decoded.ok());
  EXPECT_NE(decoded.error().find("unknown status 7"), std::string::npos) << decoded.error();

  // A distance image of another type.
  dds::Sample<semfuse_srv_dds__SemanticSlice_Response_> slice;
  SemanticSliceCodec::encodeReply({ReplyCode::kOk, "", {{0, 0}, 0.1, 0.0, cv::Mat(2, 2, CV_32FC1, cv::Scalar(1))}},
                                  *slice);
  dds::setString(slice->distance.encoding, "16UC1");
  slice->distance.step = 4;
  auto wrong_type = SemanticSliceCodec::decodeReply(*slice);
  ASSERT_FALSE(wrong_type.ok());
  EXPECT_NE(wrong_type.error().find("expected 32FC1"), std::string::npos) << wrong_type.error();
}

}  // namespace
}  // namespace semfuse::wire
