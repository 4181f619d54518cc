// Every message and service of idl/semfuse over the wire and back: encode with its codec, write
// the CDR bytes Cyclone puts on the network, read them back, decode, and compare field by field
// with the value that went in. Then what each decoder refuses, and how it says so.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "round_trip.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "semfuse/wire/status_codec.hpp"
#include "test_frames.hpp"

namespace semfuse::wire {
namespace {

Pose testPose() { return *testing::makeFrame().camera_to_world; }

// Same type, size and every element (bitwise for the test images, which hold no NaN).
void expectSameImage(const cv::Mat& expected, const cv::Mat& actual, const std::string& what) {
  ASSERT_EQ(expected.type(), actual.type()) << what;
  ASSERT_EQ(expected.size(), actual.size()) << what;
  if (!expected.empty()) {
    EXPECT_EQ(cv::norm(expected, actual, cv::NORM_INF), 0.0) << what;
  }
}

// --- messages (topics) ---

TEST(WireRoundTrip, Frame) {
  const Frame in = testing::makeFrame(16, 12);
  FrameEncoding lossless;
  lossless.depth = "32FC1";
  auto encoded = encodeFrame(in, lossless);
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  auto out = decodeFrame(*overTheWire(encoded.value().msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  const Frame& f = out.value();
  EXPECT_EQ(f.camera_id, "cam0");
  EXPECT_EQ(f.seq, 17u);
  EXPECT_EQ(f.stamp.sec, 12);
  EXPECT_EQ(f.stamp.nanosec, 345000000u);
  EXPECT_EQ(f.frame_id, "camera_optical");
  EXPECT_EQ(f.intrinsics.width, 16);
  EXPECT_EQ(f.intrinsics.height, 12);
  EXPECT_EQ(f.intrinsics.fx, 50.0);
  EXPECT_EQ(f.intrinsics.fy, 51.0);
  EXPECT_EQ(f.intrinsics.cx, 7.5);
  EXPECT_EQ(f.intrinsics.cy, 5.5);
  expectSameImage(in.depth, f.depth, "depth");
  expectSameImage(in.color, f.color, "color");
  ASSERT_TRUE(f.camera_to_world.has_value());
  EXPECT_EQ(f.camera_to_world->matrix(), in.camera_to_world->matrix());
}

TEST(WireRoundTrip, Segmentation) {
  Segmentation in;
  in.camera_id = "cam1";
  in.frame_seq = 4242;
  in.segmenter_id = "deeplab";
  in.stamp = {7, 250000000};
  in.labels.create(3, 5, CV_16UC1);
  in.confidence.create(3, 5, CV_32FC1);
  in.instances.create(3, 5, CV_16UC1);
  for (int i = 0; i < 15; ++i) {
    in.labels.at<uint16_t>(i / 5, i % 5) = static_cast<uint16_t>(i * 3);
    in.confidence.at<float>(i / 5, i % 5) = static_cast<float>(i) / 16.0f;
    in.instances.at<uint16_t>(i / 5, i % 5) = static_cast<uint16_t>(i < 5 ? 0 : 60000 + i / 5);
  }
  auto encoded = encodeSegmentation(in, "32FC1");
  ASSERT_TRUE(encoded.ok()) << encoded.error();
  auto out = decodeSegmentation(*overTheWire(encoded.value().msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().camera_id, "cam1");
  EXPECT_EQ(out.value().frame_seq, 4242u);
  EXPECT_EQ(out.value().segmenter_id, "deeplab");
  EXPECT_EQ(out.value().stamp.sec, 7);
  EXPECT_EQ(out.value().stamp.nanosec, 250000000u);
  expectSameImage(in.labels, out.value().labels, "labels");
  expectSameImage(in.confidence, out.value().confidence, "confidence");
  expectSameImage(in.instances, out.value().instances, "instances");
}

TEST(WireRoundTrip, TrackedPose) {
  TrackedPose in;
  in.camera_id = "cam2";
  in.seq = 99;
  in.stamp = {100, 5};
  in.frame_id = "world";
  in.state = PoseState::kRefined;
  in.posed = true;
  in.camera_to_world = testPose();
  in.inlier_ratio = 0.875f;
  in.residual = 0.0125f;
  in.iterations = 14;
  in.track_ms = 5.25f;
  auto out = decodeTrackedPose(*overTheWire(encodeTrackedPose(in).msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  const TrackedPose& p = out.value();
  EXPECT_EQ(p.camera_id, "cam2");
  EXPECT_EQ(p.seq, 99u);
  EXPECT_EQ(p.stamp.sec, 100);
  EXPECT_EQ(p.stamp.nanosec, 5u);
  EXPECT_EQ(p.frame_id, "world");
  EXPECT_EQ(p.state, PoseState::kRefined);
  EXPECT_TRUE(p.posed);
  EXPECT_EQ(p.camera_to_world.matrix(), in.camera_to_world.matrix());
  EXPECT_EQ(p.inlier_ratio, 0.875f);
  EXPECT_EQ(p.residual, 0.0125f);
  EXPECT_EQ(p.iterations, 14u);
  EXPECT_EQ(p.track_ms, 5.25f);
}

TEST(WireRoundTrip, ObjectEvents) {
  ObjectEvents in;
  in.update = 7;
  in.stamp = {1700000000, 42};
  in.object_count = 5;
  in.events = {{ObjectEventKind::kAppeared, 12, 3, {}},
               {ObjectEventKind::kMerged, 4, 5, {9, 10}},
               {ObjectEventKind::kSplit, 6, 5, {13}},
               {ObjectEventKind::kVanished, 2, 8, {}}};
  auto out = decodeObjectEvents(*overTheWire(encodeObjectEvents(in).msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  const ObjectEvents& e = out.value();
  EXPECT_EQ(e.update, 7u);
  EXPECT_EQ(e.stamp.sec, 1700000000);
  EXPECT_EQ(e.stamp.nanosec, 42u);
  EXPECT_EQ(e.object_count, 5u);
  ASSERT_EQ(e.events.size(), 4u);
  for (std::size_t i = 0; i < e.events.size(); ++i) {
    EXPECT_EQ(e.events[i].kind, in.events[i].kind) << i;
    EXPECT_EQ(e.events[i].id, in.events[i].id) << i;
    EXPECT_EQ(e.events[i].label, in.events[i].label) << i;
    EXPECT_EQ(e.events[i].others, in.events[i].others) << i;
  }
}

TEST(WireRoundTrip, LabelLegend) {
  LabelLegend in;
  in.name = "kitchen";
  in.labels = {{0, "other", {0, 0, 0}}, {3, "table", {200, 100, 50}}, {17, "chair", {1, 2, 3}}};
  in.background_ids = {0, 17};
  auto out = decodeLegend(*overTheWire(encodeLegend(in, {5, 6}).msg()));
  ASSERT_TRUE(out.ok()) << out.error();
  EXPECT_EQ(out.value().name, "kitchen");
  ASSERT_EQ(out.value().labels.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(out.value().labels[i].id, in.labels[i].id);
    EXPECT_EQ(out.value().labels[i].name, in.labels[i].name);
    EXPECT_EQ(out.value().labels[i].rgb, in.labels[i].rgb);
  }
  EXPECT_EQ(out.value().background_ids, in.background_ids);
}

ServerStatus testStatus() {
  ServerStatus s;
  s.server_id = "semfuse-server@host";
  s.version = "1.2.3";
  s.uptime_s = 3600.5;
  s.frames_received = 1000;
  s.frames_posed = 1000;
  s.frames_integrated = 990;
  s.frames_skipped = 7;
  s.frames_lost = 3;
  s.segmentations_received = 500;
  s.segmentations_integrated = 480;
  s.dropped = {{"queue_full", "cam0", 7}, {"waited_too_long", "", 2}};
  s.rejected = {{"invalid_frame", "cam1", 4}};
  s.queued_frames = 2;
  s.pending_segmentations = 5;
  s.history_frames = 30;
  s.voxel_size = 0.01;
  s.truncation = 0.04;
  s.allocated_voxels = 123456789;
  s.allocated_blocks = 4321;
  s.map_bytes = 987654321;
  s.rss_bytes = 1ull << 31;
  s.cameras = {{"cam0", 1, 1000, 1000, 995, 990, 5, 3, 29.5F, 0.25F, false, "", 0, 2},
               {"cam1", 3, 8, 9, 0, 0, 0, 9, 0.0F, 12.0F, true, "not placed in the map yet", 9, 0}};
  s.last_errors = {{12.5, "query raycast", "layers must be ..."}, {13.0, "admin", "disk full"}};
  s.map_file = "/var/lib/semfuse/map.vdb";
  s.last_save_ok = true;
  s.last_save_age_s = 42.0;
  s.stages = {{"frame_decode", 120, 1.5F, 3.25F, 9.0F}, {"integrate", 118, 4.0F, 7.5F, 30.0F}};
  s.map_revision = 9000000000ull;
  s.distance_field_revision = 8999999990ull;
  s.snapshot_bytes = 123456789ull;
  return s;
}

void expectSameStatus(const ServerStatus& in, const ServerStatus& out) {
  EXPECT_EQ(out.server_id, in.server_id);
  EXPECT_EQ(out.version, in.version);
  EXPECT_EQ(out.uptime_s, in.uptime_s);
  EXPECT_EQ(out.frames_received, in.frames_received);
  EXPECT_EQ(out.frames_posed, in.frames_posed);
  EXPECT_EQ(out.frames_integrated, in.frames_integrated);
  EXPECT_EQ(out.frames_skipped, in.frames_skipped);
  EXPECT_EQ(out.frames_lost, in.frames_lost);
  EXPECT_EQ(out.segmentations_received, in.segmentations_received);
  EXPECT_EQ(out.segmentations_integrated, in.segmentations_integrated);
  auto same_counters = [](const std::vector<ReasonCount>& a, const std::vector<ReasonCount>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].reason, b[i].reason);
      EXPECT_EQ(a[i].camera_id, b[i].camera_id);
      EXPECT_EQ(a[i].count, b[i].count);
    }
  };
  same_counters(in.dropped, out.dropped);
  same_counters(in.rejected, out.rejected);
  EXPECT_EQ(out.queued_frames, in.queued_frames);
  EXPECT_EQ(out.pending_segmentations, in.pending_segmentations);
  EXPECT_EQ(out.history_frames, in.history_frames);
  EXPECT_EQ(out.voxel_size, in.voxel_size);
  EXPECT_EQ(out.truncation, in.truncation);
  EXPECT_EQ(out.allocated_voxels, in.allocated_voxels);
  EXPECT_EQ(out.allocated_blocks, in.allocated_blocks);
  EXPECT_EQ(out.map_bytes, in.map_bytes);
  EXPECT_EQ(out.rss_bytes, in.rss_bytes);
  ASSERT_EQ(out.cameras.size(), in.cameras.size());
  for (size_t i = 0; i < in.cameras.size(); ++i) {
    const CameraStatus &a = in.cameras[i], &b = out.cameras[i];
    EXPECT_EQ(b.camera_id, a.camera_id);
    EXPECT_EQ(b.tracking_state, a.tracking_state);
    EXPECT_EQ(b.last_seq, a.last_seq);
    EXPECT_EQ(b.frames_received, a.frames_received);
    EXPECT_EQ(b.frames_posed, a.frames_posed);
    EXPECT_EQ(b.frames_integrated, a.frames_integrated);
    EXPECT_EQ(b.frames_skipped, a.frames_skipped);
    EXPECT_EQ(b.frames_lost, a.frames_lost);
    EXPECT_EQ(b.frame_rate_hz, a.frame_rate_hz);
    EXPECT_EQ(b.last_frame_age_s, a.last_frame_age_s);
    EXPECT_EQ(b.stale, a.stale);
    EXPECT_EQ(b.lost_reason, a.lost_reason);
    EXPECT_EQ(b.frames_since_lost, a.frames_since_lost);
    EXPECT_EQ(b.relocalisations, a.relocalisations);
  }
  ASSERT_EQ(out.last_errors.size(), in.last_errors.size());
  for (size_t i = 0; i < in.last_errors.size(); ++i) {
    EXPECT_EQ(out.last_errors[i].stamp_s, in.last_errors[i].stamp_s);
    EXPECT_EQ(out.last_errors[i].source, in.last_errors[i].source);
    EXPECT_EQ(out.last_errors[i].message, in.last_errors[i].message);
  }
  EXPECT_EQ(out.map_file, in.map_file);
  EXPECT_EQ(out.last_save_ok, in.last_save_ok);
  EXPECT_EQ(out.last_save_age_s, in.last_save_age_s);
  EXPECT_EQ(out.map_revision, in.map_revision);
  EXPECT_EQ(out.distance_field_revision, in.distance_field_revision);
  EXPECT_EQ(out.snapshot_bytes, in.snapshot_bytes);
  ASSERT_EQ(out.stages.size(), in.stages.size());
  for (size_t i = 0; i < in.stages.size(); ++i) {
    EXPECT_EQ(out.stages[i].stage, in.stages[i].stage);
    EXPECT_EQ(out.stages[i].count, in.stages[i].count);
    EXPECT_EQ(out.stages[i].p50_ms, in.stages[i].p50_ms);
    EXPECT_EQ(out.stages[i].p95_ms, in.stages[i].p95_ms);
    EXPECT_EQ(out.stages[i].max_ms, in.stages[i].max_ms);
  }
}

TEST(WireRoundTrip, ServerStatus) {
  const ServerStatus in = testStatus();
  dds::Sample<semfuse_msg_dds__ServerStatus_> sent;
  encodeServerStatus(in, {1700000000, 250}, *sent);
  auto received = overTheWire(*sent);
  EXPECT_EQ(received->header.stamp.sec, 1700000000);
  EXPECT_EQ(received->header.stamp.nanosec, 250u);
  EXPECT_STREQ(received->header.frame_id, "world");
  auto out = decodeServerStatus(*received);
  ASSERT_TRUE(out.ok()) << out.error();
  expectSameStatus(in, out.value());
}

// --- services: requests ---

TEST(WireRoundTrip, ServiceRequests) {
  const RaycastRequest raycast{testPose(), {640, 480, 525.0, 526.5, 319.5, 239.5}, kDepthLayer | kLabelsLayer, 6.5F};
  const RaycastRequest r = requestRoundTrip<RaycastCodec>(raycast);
  EXPECT_EQ(r.camera_to_world.matrix(), raycast.camera_to_world.matrix());
  EXPECT_EQ(r.intrinsics.width, 640);
  EXPECT_EQ(r.intrinsics.height, 480);
  EXPECT_EQ(r.intrinsics.fx, 525.0);
  EXPECT_EQ(r.intrinsics.fy, 526.5);
  EXPECT_EQ(r.intrinsics.cx, 319.5);
  EXPECT_EQ(r.intrinsics.cy, 239.5);
  EXPECT_EQ(r.layers, kDepthLayer | kLabelsLayer);
  EXPECT_EQ(r.max_range, 6.5F);

  const LabelsAtRequest labels_at{{{0.0, 0.0, 0.75}, {-1.5, 2.25, 1e-3}, {1e6, -1e6, 3.0}}};
  EXPECT_EQ(requestRoundTrip<LabelsAtCodec>(labels_at).points, labels_at.points);
  EXPECT_TRUE(requestRoundTrip<LabelsAtCodec>({}).points.empty());

  const Box box{{-1.0, -2.0, 0.0}, {1.5, 2.5, 3.0}};
  const Box region = requestRoundTrip<RegionCodec>(box);
  EXPECT_EQ(region.min, box.min);
  EXPECT_EQ(region.max, box.max);

  ObjectsRequest asked;
  asked.label = 5;
  asked.min_voxels = 250;
  const ObjectsRequest objects = requestRoundTrip<ObjectsCodec>(asked);
  EXPECT_EQ(objects.label, 5);
  EXPECT_EQ(objects.min_voxels, 250u);
  EXPECT_FALSE(objects.near.has_value());
  EXPECT_FALSE(objects.include_fragments);
  EXPECT_EQ(objects.max_age_s, 0.0);
  asked.near = Eigen::Vector3d(1.0, -2.5, 0.75);
  asked.radius = 0.4;
  asked.include_fragments = true;
  asked.max_age_s = 1.5;
  const ObjectsRequest near = requestRoundTrip<ObjectsCodec>(asked);
  ASSERT_TRUE(near.near.has_value());
  EXPECT_EQ(*near.near, *asked.near);
  EXPECT_EQ(near.radius, 0.4);
  EXPECT_TRUE(near.include_fragments);
  EXPECT_EQ(near.max_age_s, 1.5);

  const MeshRequest first = requestRoundTrip<MeshCodec>({box, 0, 0, 0});
  ASSERT_TRUE(first.box.has_value());
  EXPECT_EQ(first.box->min, box.min);
  EXPECT_EQ(first.box->max, box.max);
  EXPECT_EQ(first.mesh_id, 0u);
  EXPECT_EQ(first.object_id, 0u);
  const MeshRequest later = requestRoundTrip<MeshCodec>({std::nullopt, 77, 3, 0});
  EXPECT_FALSE(later.box.has_value());
  EXPECT_EQ(later.mesh_id, 77u);
  EXPECT_EQ(later.chunk_index, 3u);
  const MeshRequest object = requestRoundTrip<MeshCodec>({std::nullopt, 0, 0, 42});
  EXPECT_EQ(object.object_id, 42u);

  for (AdminCommand command : {AdminCommand::kStats, AdminCommand::kSave, AdminCommand::kLoad, AdminCommand::kReset}) {
    const AdminRequest admin = requestRoundTrip<AdminCodec>({command, "/tmp/map.vdb"});
    EXPECT_EQ(admin.command, command);
    EXPECT_EQ(admin.path, "/tmp/map.vdb");
  }
}

// --- services: replies ---

RaycastImages testImages() {
  RaycastImages images;
  images.depth.create(3, 4, CV_32FC1);
  images.normals.create(3, 4, CV_32FC3);
  images.labels.create(3, 4, CV_16UC1);
  images.confidence.create(3, 4, CV_32FC1);
  images.color.create(3, 4, CV_8UC3);
  for (int v = 0; v < 3; ++v) {
    for (int u = 0; u < 4; ++u) {
      images.depth.at<float>(v, u) = 0.5f + 0.25f * static_cast<float>(u + 4 * v);
      images.normals.at<cv::Vec3f>(v, u) = cv::Vec3f(0.0f, static_cast<float>(u) / 4.0f, -1.0f);
      images.labels.at<uint16_t>(v, u) = static_cast<uint16_t>(u * 100 + v);
      images.confidence.at<float>(v, u) = static_cast<float>(v) / 3.0f;
      images.color.at<cv::Vec3b>(v, u) = cv::Vec3b(static_cast<uint8_t>(u * 60), 10, static_cast<uint8_t>(v * 80));
    }
  }
  return images;
}

TEST(WireRoundTrip, RaycastReplyDecodedAndTaken) {
  const RaycastImages in = testImages();
  const auto check = [&](const RaycastImages& out) {
    expectSameImage(in.depth, out.depth, "depth");
    expectSameImage(in.normals, out.normals, "normals");
    expectSameImage(in.labels, out.labels, "labels");
    expectSameImage(in.confidence, out.confidence, "confidence");
    expectSameImage(in.color, out.color, "color");
  };
  check(replyRoundTrip<RaycastCodec>(okReply(in)).value);

  dds::Sample<semfuse_srv_dds__Raycast_Response_> sent;
  RaycastCodec::encodeReply(okReply(in), *sent);
  auto received = overTheWire(*sent);
  const uint8_t* depth_pixels = received->depth.data._buffer;
  auto taken = RaycastCodec::takeReply(*received);
  ASSERT_TRUE(taken.ok()) << taken.error();
  check(taken.value().value);
  EXPECT_EQ(taken.value().value.depth.data, depth_pixels);  // handed over, not copied
  EXPECT_EQ(received->depth.data._buffer, nullptr);

  // Layers not asked for stay empty.
  RaycastImages depth_only;
  depth_only.depth = in.depth;
  const RaycastImages out = replyRoundTrip<RaycastCodec>(okReply(depth_only)).value;
  expectSameImage(in.depth, out.depth, "depth");
  EXPECT_TRUE(out.normals.empty() && out.labels.empty() && out.confidence.empty() && out.color.empty());
}

TEST(WireRoundTrip, QueryReplies) {
  const std::vector<VoxelSample> samples = {{true, 7, 0.75F, -0.5F, 12.0F}, {false, 0, 0.0F, 1.0F, 0.0F}};
  const auto labels_at = replyRoundTrip<LabelsAtCodec>(okReply(samples)).value;
  ASSERT_EQ(labels_at.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(labels_at[i].observed, samples[i].observed);
    EXPECT_EQ(labels_at[i].label, samples[i].label);
    EXPECT_EQ(labels_at[i].confidence, samples[i].confidence);
    EXPECT_EQ(labels_at[i].tsdf, samples[i].tsdf);
    EXPECT_EQ(labels_at[i].weight, samples[i].weight);
  }

  RegionSummary summary;
  summary.histogram = {{0, 10, 0.001}, {3, 2500, 0.25}};
  summary.observed_voxels = 100000;
  summary.occupied_voxels = 30000;
  summary.free_voxels = 70000;
  summary.occupancy = 0.3;
  const RegionSummary region = replyRoundTrip<RegionCodec>(okReply(summary)).value;
  ASSERT_EQ(region.histogram.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(region.histogram[i].label, summary.histogram[i].label);
    EXPECT_EQ(region.histogram[i].surface_voxels, summary.histogram[i].surface_voxels);
    EXPECT_EQ(region.histogram[i].area_m2, summary.histogram[i].area_m2);
  }
  EXPECT_EQ(region.observed_voxels, 100000u);
  EXPECT_EQ(region.occupied_voxels, 30000u);
  EXPECT_EQ(region.free_voxels, 70000u);
  EXPECT_EQ(region.occupancy, 0.3);

  std::vector<ObjectInstance> found(2);
  found[0].id = 1;
  found[0].label = 5;
  found[0].bbox_min = {0.0, 0.5, 0.0};
  found[0].bbox_max = {1.0, 1.5, 0.75};
  found[0].centroid = {0.5, 1.0, 0.25};
  found[0].voxel_count = 4096;
  found[0].mean_confidence = 0.625F;
  found[0].area_m2 = 1.6384;
  found[0].box_center = {0.5, 1.0, 0.375};
  found[0].box_half_extents = {0.6, 0.4, 0.375};
  found[0].box_rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  found[0].frames = {{"kitchen-left", 412}, {"arm", 7}};
  found[0].frame_count = 230;
  found[1].id = 2;
  found[1].label = 9;
  found[1].bbox_min = {-2.0, -2.0, -2.0};
  found[1].bbox_max = {-1.0, -1.0, -1.0};
  found[1].centroid = {-1.5, -1.5, -1.5};
  found[1].voxel_count = 100;
  found[1].mean_confidence = 1.0F;
  found[1].area_m2 = 0.04;
  found[1].fragment = true;
  const auto objects = replyRoundTrip<ObjectsCodec>(okReply(found)).value;
  ASSERT_EQ(objects.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(objects[i].id, found[i].id);
    EXPECT_EQ(objects[i].label, found[i].label);
    EXPECT_EQ(objects[i].bbox_min, found[i].bbox_min);
    EXPECT_EQ(objects[i].bbox_max, found[i].bbox_max);
    EXPECT_EQ(objects[i].centroid, found[i].centroid);
    EXPECT_EQ(objects[i].voxel_count, found[i].voxel_count);
    EXPECT_EQ(objects[i].mean_confidence, found[i].mean_confidence);
    EXPECT_EQ(objects[i].area_m2, found[i].area_m2);
    EXPECT_EQ(objects[i].box_center, found[i].box_center);
    EXPECT_EQ(objects[i].box_half_extents, found[i].box_half_extents);
    EXPECT_EQ(objects[i].box_rotation.coeffs(), found[i].box_rotation.coeffs());
    EXPECT_EQ(objects[i].fragment, found[i].fragment);
    EXPECT_EQ(objects[i].frame_count, found[i].frame_count);
    ASSERT_EQ(objects[i].frames.size(), found[i].frames.size());
    for (size_t k = 0; k < found[i].frames.size(); ++k) {
      EXPECT_EQ(objects[i].frames[k].camera_id, found[i].frames[k].camera_id);
      EXPECT_EQ(objects[i].frames[k].seq, found[i].frames[k].seq);
    }
  }

  MeshChunk chunk;
  chunk.mesh_id = 12;
  chunk.chunk_index = 1;
  chunk.chunk_count = 3;
  chunk.total_bytes = 2500;
  chunk.vertex_count = 800;
  chunk.face_count = 1500;
  chunk.ply = {'p', 'l', 'y', '\n', 0, 255, 7};
  const MeshChunk mesh = replyRoundTrip<MeshCodec>(okReply(chunk)).value;
  EXPECT_EQ(mesh.mesh_id, 12u);
  EXPECT_EQ(mesh.chunk_index, 1u);
  EXPECT_EQ(mesh.chunk_count, 3u);
  EXPECT_EQ(mesh.total_bytes, 2500u);
  EXPECT_EQ(mesh.vertex_count, 800u);
  EXPECT_EQ(mesh.face_count, 1500u);
  EXPECT_EQ(mesh.ply, chunk.ply);

  ServiceReply<ServerStatus> saved = okReply(testStatus());
  saved.message = "saved";
  const auto admin = replyRoundTrip<AdminCodec>(saved);
  EXPECT_TRUE(admin.ok());
  EXPECT_EQ(admin.message, "saved");
  expectSameStatus(saved.value, admin.value);
}

TEST(WireRoundTrip, ErrorRepliesKeepTheirCodeAndMessage) {
  const auto too_large = replyRoundTrip<RaycastCodec>(
      ServiceReply<RaycastImages>::failure(ReplyCode::kTooLarge, "raycast of 9000x9000 exceeds the limit"));
  EXPECT_EQ(too_large.code, ReplyCode::kTooLarge);
  EXPECT_EQ(too_large.message, "raycast of 9000x9000 exceeds the limit");
  EXPECT_TRUE(too_large.value.depth.empty());

  const auto gone = replyRoundTrip<MeshCodec>(ServiceReply<MeshChunk>::failure(ReplyCode::kNotFound, "mesh 3 is gone"));
  EXPECT_EQ(gone.code, ReplyCode::kNotFound);
  EXPECT_EQ(gone.message, "mesh 3 is gone");

  // A failed admin action still carries the server's status.
  ServiceReply<ServerStatus> failed = ServiceReply<ServerStatus>::failure(ReplyCode::kUnavailable, "disk full");
  failed.value = testStatus();
  const auto admin = replyRoundTrip<AdminCodec>(failed);
  EXPECT_EQ(admin.code, ReplyCode::kUnavailable);
  EXPECT_EQ(admin.message, "disk full");
  expectSameStatus(failed.value, admin.value);
}

// --- what the decoders refuse ---

TEST(WireRoundTrip, MalformedRequestsAreRefusedWithTheirReason) {
  dds::Sample<semfuse_srv_dds__Raycast_Request_> raycast;
  RaycastCodec::encodeRequest({testPose(), {640, 480, 500, 500, 320, 240}, kDepthLayer, 0.0F}, *raycast);
  raycast->intrinsics.width = 3000000000u;
  EXPECT_EQ(RaycastCodec::decodeRequest(*raycast).error(), "raycast: image size 3000000000x480 is beyond any image");

  dds::Sample<semfuse_srv_dds__LabelsAt_Request_> labels_at;
  LabelsAtCodec::encodeRequest({{{1.0, 2.0, 3.0}, {4.0, 5.0, 6.0}}}, *labels_at);
  labels_at->points._length = 3;
  EXPECT_EQ(LabelsAtCodec::decodeRequest(*labels_at).error(),
            "labels_at points: truncated sequence, length 3 exceeds its allocation of 2");
  labels_at->points._length = 2;

  dds::Sample<semfuse_srv_dds__Admin_Request_> admin;
  AdminCodec::encodeRequest({AdminCommand::kSave, ""}, *admin);
  admin->command = 9;
  EXPECT_EQ(AdminCodec::decodeRequest(*admin).error(), "unknown admin command 9 (0 stats, 1 save, 2 load, 3 reset)");
}

TEST(WireRoundTrip, MalformedRepliesAreRefusedWithTheirReason) {
  dds::Sample<semfuse_srv_dds__Raycast_Response_> raycast;
  RaycastCodec::encodeReply(okReply(testImages()), *raycast);
  raycast->depth.data._length -= 1;
  EXPECT_EQ(RaycastCodec::decodeReply(*raycast).error(), "depth: image data shorter than its 4x3 size");
  EXPECT_EQ(RaycastCodec::takeReply(*raycast).error(), "depth: image data shorter than its 4x3 size");
  raycast->depth.data._length += 1;
  dds::setString(raycast->labels.encoding, "mono8");  // bytes enough, but not the labels' type
  EXPECT_EQ(RaycastCodec::decodeReply(*raycast).error(), "labels: 8UC1 image, expected 16UC1");
  dds::setString(raycast->labels.encoding, "yuv422");
  EXPECT_EQ(RaycastCodec::decodeReply(*raycast).error(), "labels: unsupported image encoding 'yuv422'");

  // The server's error wins over a value that does not decode.
  raycast->status = static_cast<int32_t>(ReplyCode::kInternal);
  dds::setString(raycast->message, "request failed: out of memory");
  auto failed = RaycastCodec::decodeReply(*raycast);
  ASSERT_TRUE(failed.ok()) << failed.error();
  EXPECT_EQ(failed.value().code, ReplyCode::kInternal);
  EXPECT_EQ(failed.value().message, "request failed: out of memory");
  EXPECT_TRUE(failed.value().value.labels.empty());

  dds::Sample<semfuse_srv_dds__Mesh_Response_> mesh;
  MeshChunk chunk;
  chunk.ply = {1, 2, 3};
  MeshCodec::encodeReply(okReply(chunk), *mesh);
  mesh->ply._maximum = 2;
  EXPECT_EQ(MeshCodec::decodeReply(*mesh).error(),
            "mesh ply: truncated sequence, length 3 exceeds its allocation of 2");
  mesh->ply._maximum = 3;

  dds::Sample<semfuse_msg_dds__ServerStatus_> status;
  encodeServerStatus(testStatus(), {}, *status);
  status->cameras._length = 5;
  EXPECT_EQ(decodeServerStatus(*status).error(),
            "status cameras: truncated sequence, length 5 exceeds its allocation of 2");
  status->cameras._length = 2;
  dds::Sample<semfuse_srv_dds__Admin_Response_> admin;
  AdminCodec::encodeReply(okReply(testStatus()), *admin);
  admin->server_status.rejected._length = 4;
  EXPECT_EQ(AdminCodec::decodeReply(*admin).error(),
            "status rejected: truncated sequence, length 4 exceeds its allocation of 1");
  admin->server_status.rejected._length = 1;
}

}  // namespace
}  // namespace semfuse::wire
