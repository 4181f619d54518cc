// fuzz_make_seeds: writes the seed corpus of every fuzz target (fuzz/corpus/<target>/seed-*),
// small valid inputs made with semfuse's own encoders, so that the fuzzers start from samples
// that decode and the replay tests check that they still do.
//   fuzz_make_seeds --out fuzz/corpus
// Findings that became regression inputs live beside the seeds as crash-* / regress-* files and
// are not touched by this program.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "semfuse/core/legend.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/ply_writer.hpp"
#include "semfuse/volume/map_file.hpp"
#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/map_update_codecs.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/rvl_codec.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "semfuse/wire/status_codec.hpp"
#include "tiny_map.hpp"

namespace {
namespace fs = std::filesystem;
using namespace semfuse;
using Bytes = std::vector<uint8_t>;

fs::path g_out;

void write(const std::string& target, const std::string& name, const Bytes& bytes) {
  const fs::path folder = g_out / target;
  fs::create_directories(folder);
  std::ofstream out(folder / ("seed-" + name), std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}
void writeText(const std::string& target, const std::string& name, const std::string& text) {
  write(target, name, Bytes(text.begin(), text.end()));
}
Bytes withSelector(uint8_t selector, Bytes bytes) {
  bytes.insert(bytes.begin(), selector);
  return bytes;
}
template <class T>
Bytes cdr(const T& msg) {
  return dds::serialize(msg);
}

// An 8x6 frame: a depth ramp, a colour gradient, a pose.
Frame smallFrame() {
  Frame frame;
  frame.camera_id = "cam";
  frame.frame_id = "camera";
  frame.seq = 7;
  frame.stamp = {12, 345};
  frame.intrinsics = {8, 6, 10.0, 10.0, 3.5, 2.5};
  frame.depth.create(6, 8, CV_32FC1);
  frame.color.create(6, 8, CV_8UC3);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      frame.depth.at<float>(y, x) = x == 0 ? 0.0f : 0.5f + 0.1f * static_cast<float>(x + y);
      frame.color.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uint8_t>(30 * x), static_cast<uint8_t>(40 * y), 90);
    }
  }
  Pose pose = Pose::Identity();
  pose.translation() = Eigen::Vector3d(0.1, -0.2, 0.3);
  frame.camera_to_world = pose;
  return frame;
}

void frameSeeds(const Frame& frame) {
  for (const std::string depth : {"16UC1", "32FC1", "png16", "rvl"}) {
    for (const std::string color : {"", "rgb8", "bgr8", "jpeg", "png"}) {
      wire::FrameEncoding encoding;
      encoding.depth = depth;
      encoding.color = color;
      auto encoded = wire::encodeFrame(frame, encoding);
      if (!encoded) throw std::runtime_error(encoded.error());
      write("frame_cdr", depth + "-" + (color.empty() ? "none" : color), cdr(encoded.value().msg()));
    }
  }
  Frame no_pose = frame;
  no_pose.camera_to_world.reset();
  write("frame_cdr", "no-pose", cdr(wire::encodeFrame(no_pose).value().msg()));
}

void imagePayloadSeeds(const Frame& frame) {
  const auto header = [](uint8_t kind, int w, int h) {
    return Bytes{kind, static_cast<uint8_t>(w & 0xff), static_cast<uint8_t>(w >> 8), static_cast<uint8_t>(h & 0xff),
                 static_cast<uint8_t>(h >> 8)};
  };
  cv::Mat bgr;
  cv::cvtColor(frame.color, bgr, cv::COLOR_RGB2BGR);
  const auto encode = [](const char* ext, const cv::Mat& image, std::vector<int> params) {
    Bytes bytes;
    cv::imencode(ext, image, bytes, params);
    return bytes;
  };
  const auto seed = [&](uint8_t kind, const Bytes& payload) {
    // Header then payload, built in one buffer of the final size (inserting into the 5-byte
    // header's vector trips a GCC 12 -Warray-bounds false positive).
    const Bytes head = header(kind, frame.depth.cols, frame.depth.rows);
    Bytes bytes(head.size() + payload.size());
    std::copy(head.begin(), head.end(), bytes.begin());
    std::copy(payload.begin(), payload.end(), bytes.begin() + static_cast<std::ptrdiff_t>(head.size()));
    return bytes;
  };
  write("image_payload", "color-png", seed(0, encode(".png", bgr, {})));
  write("image_payload", "color-jpeg", seed(1, encode(".jpg", bgr, {cv::IMWRITE_JPEG_QUALITY, 80})));
  write("image_payload", "color-jpeg-progressive",
        seed(1, encode(".jpg", bgr, {cv::IMWRITE_JPEG_QUALITY, 50, cv::IMWRITE_JPEG_PROGRESSIVE, 1})));
  cv::Mat units;
  frame.depth.convertTo(units, CV_16U, 1000.0);
  write("image_payload", "depth-png16", seed(2, encode(".png", units, {})));
  write("image_payload", "depth-rvl", seed(3, wire::encodeRvl(units).value()));
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  write("image_payload", "color-png-gray", seed(0, encode(".png", gray, {})));
}

void segmentationSeeds() {
  Segmentation segmentation;
  segmentation.camera_id = "cam";
  segmentation.frame_seq = 7;
  segmentation.segmenter_id = "seg";
  segmentation.labels.create(6, 8, CV_16UC1);
  segmentation.confidence.create(6, 8, CV_32FC1);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) {
      segmentation.labels.at<uint16_t>(y, x) = static_cast<uint16_t>((x + y) % 21);
      segmentation.confidence.at<float>(y, x) = 0.1f * static_cast<float>(x);
    }
  }
  for (const std::string encoding : {"8UC1", "32FC1"}) {
    write("segmentation_cdr", encoding, cdr(wire::encodeSegmentation(segmentation, encoding).value().msg()));
  }
  Segmentation no_confidence = segmentation;
  no_confidence.confidence.release();
  write("segmentation_cdr", "none", cdr(wire::encodeSegmentation(no_confidence).value().msg()));
  Segmentation panoptic = segmentation;  // two instances, the left and right halves
  panoptic.instances.create(6, 8, CV_16UC1);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) panoptic.instances.at<uint16_t>(y, x) = static_cast<uint16_t>(x < 4 ? 3 : 9);
  write("segmentation_cdr", "instances", cdr(wire::encodeSegmentation(panoptic).value().msg()));
}

// Replies the client decodes, as the server encodes them (common/wire/service_codecs.hpp):
// a 4x3 raycast (depth, normals, labels), a status, mesh chunks.
void clientReplySeeds() {
  ServiceReply<RaycastImages> view;
  view.value.depth = cv::Mat(3, 4, CV_32FC1, cv::Scalar(1.5f));
  view.value.normals = cv::Mat(3, 4, CV_32FC3, cv::Scalar(0.0f, 0.0f, -1.0f));
  view.value.labels = cv::Mat(3, 4, CV_16UC1, cv::Scalar(7));
  dds::Sample<semfuse_srv_dds__Raycast_Response_> raycast;
  wire::RaycastCodec::encodeReply(view, *raycast);
  write("client_messages_cdr", "raycast-reply", withSelector(2, cdr(*raycast)));

  ServerStatus status;
  status.server_id = "server";
  status.version = "0.1";
  status.frames_received = 10;
  status.frames_integrated = 9;
  status.dropped = {{"queue_full", "cam", 1}};
  status.cameras.resize(1);
  status.cameras[0].camera_id = "cam";
  status.last_errors = {{0.0, "frames", "depth size 4x3 does not match 8x6"}};
  dds::Sample<semfuse_msg_dds__ServerStatus_> status_message;
  wire::encodeServerStatus(status, {}, *status_message);
  write("client_messages_cdr", "status", withSelector(3, cdr(*status_message)));

  const std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nend_header\n";
  for (uint32_t chunks : {1u, 2u}) {
    ServiceReply<MeshChunk> chunk;
    chunk.value.mesh_id = 42;
    chunk.value.chunk_count = chunks;
    chunk.value.total_bytes = chunks * ply.size();
    chunk.value.ply.assign(ply.begin(), ply.end());
    dds::Sample<semfuse_srv_dds__Mesh_Response_> mesh;
    wire::MeshCodec::encodeReply(chunk, *mesh);
    write("client_messages_cdr", "mesh-reply-of-" + std::to_string(chunks), withSelector(4, cdr(*mesh)));
  }
}

void clientMessageSeeds() {
  write("client_messages_cdr", "legend-voc", withSelector(0, cdr(wire::encodeLegend(*builtinLegend("voc")).msg())));
  LabelLegend small{"small", {{0, "other", {0, 0, 0}}, {4, "cup", {200, 10, 10}}}, {0}};
  write("client_messages_cdr", "legend-small", withSelector(0, cdr(wire::encodeLegend(small).msg())));
  TrackedPose pose;
  pose.camera_id = "cam";
  pose.seq = 3;
  pose.state = PoseState::kTracked;
  pose.camera_to_world = Pose::Identity();
  pose.camera_to_world.translation() = Eigen::Vector3d(1, 2, 3);
  pose.inlier_ratio = 0.8f;
  write("client_messages_cdr", "tracked-pose", withSelector(1, cdr(wire::encodeTrackedPose(pose).msg())));
  pose.state = PoseState::kLost;
  write("client_messages_cdr", "lost-pose", withSelector(1, cdr(wire::encodeTrackedPose(pose).msg())));
  ObjectEvents events;
  events.update = 2;
  events.object_count = 3;
  events.events = {{ObjectEventKind::kAppeared, 4, 7, {}}, {ObjectEventKind::kMerged, 1, 7, {2, 3}}};
  write("client_messages_cdr", "object-events", withSelector(5, cdr(wire::encodeObjectEvents(events).msg())));
  clientReplySeeds();
}

void rosSeeds(const Frame& frame) {
  cv::Mat units;
  frame.depth.convertTo(units, CV_16U, 1000.0);
  cv::Mat gray;
  cv::cvtColor(frame.color, gray, cv::COLOR_RGB2GRAY);
  const Stamp stamp{1, 2};
  write("ros_image_cdr", "16UC1", cdr(wire::matToImage(units, "16UC1", stamp, "cam").value().msg()));
  write("ros_image_cdr", "32FC1", cdr(wire::matToImage(frame.depth, "32FC1", stamp, "cam").value().msg()));
  write("ros_image_cdr", "rgb8", cdr(wire::matToImage(frame.color, "rgb8", stamp, "cam").value().msg()));
  write("ros_image_cdr", "bgr8", cdr(wire::matToImage(frame.color, "bgr8", stamp, "cam").value().msg()));
  write("ros_image_cdr", "mono8", cdr(wire::matToImage(gray, "mono8", stamp, "cam").value().msg()));
  {
    // Big-endian mono16 with padded rows, which matToImage never writes.
    auto owned = wire::matToImage(units, "16UC1", stamp, "cam").value();
    auto& msg = owned.msg();
    const uint32_t step = msg.step + 4;
    std::vector<uint8_t> padded(std::size_t{step} * msg.height, 0);
    for (uint32_t y = 0; y < msg.height; ++y) {
      for (uint32_t i = 0; i < msg.step; i += 2) {
        padded[y * step + i] = msg.data._buffer[y * msg.step + i + 1];
        padded[y * step + i + 1] = msg.data._buffer[y * msg.step + i];
      }
    }
    msg.step = step;
    msg.is_bigendian = 1;
    msg.encoding = owned.keepString("mono16");
    owned.keepSequence(msg.data, std::move(padded));
    write("ros_image_cdr", "mono16-bigendian-padded", cdr(msg));
  }
  for (const auto& [format, ext] :
       {std::pair<std::string, std::string>{"jpeg", ".jpg"}, {"png", ".png"}, {"rgb8; jpeg compressed bgr8", ".jpg"}}) {
    cv::Mat bgr;
    cv::cvtColor(frame.color, bgr, cv::COLOR_RGB2BGR);
    Bytes payload;
    cv::imencode(ext, bgr, payload);
    wire::OwnedMessage<sensor_msgs_msg_dds__CompressedImage_> owned;
    wire::fillHeader(owned, owned.msg().header, stamp, "cam");
    owned.msg().format = owned.keepString(format);
    owned.keepSequence(owned.msg().data, payload);
    write("ros_compressed_image_cdr", format.substr(0, 4) + (format.size() > 4 ? "-long" : ""), cdr(owned.msg()));
  }
  {
    Bytes payload;
    cv::imencode(".png", units, payload);
    wire::OwnedMessage<sensor_msgs_msg_dds__CompressedImage_> owned;
    wire::fillHeader(owned, owned.msg().header, stamp, "cam");
    owned.msg().format = owned.keepString("16UC1; png compressed");
    owned.keepSequence(owned.msg().data, payload);
    write("ros_compressed_image_cdr", "png16", cdr(owned.msg()));
  }
  // compressed_depth_image_transport's images: millimetres as PNG and RVL, and 32FC1 as its
  // quantised inverse depth (a = 10100, b = -1009: its defaults) in RVL.
  for (const std::string compression : {"png", "rvl"}) {
    write("ros_compressed_image_cdr", "compressed-depth-" + compression,
          cdr(wire::compressedDepthFromMillimetres(units, compression, stamp, "cam").value().msg()));
  }
  {
    cv::Mat inverse(units.size(), CV_16UC1);
    for (int y = 0; y < units.rows; ++y) {
      for (int x = 0; x < units.cols; ++x) {
        const float metres = frame.depth.at<float>(y, x);
        inverse.at<uint16_t>(y, x) = metres > 0.0f ? static_cast<uint16_t>(10100.0f / metres - 1009.0f) : 0;
      }
    }
    auto owned = wire::compressedDepthFromMillimetres(inverse, "rvl", stamp, "cam").value();
    auto& msg = owned.msg();
    msg.format = owned.keepString("32FC1; compressedDepth rvl");
    const float params[2] = {10100.0f, -1009.0f};
    for (int i = 0; i < 2; ++i) {  // little-endian, after the int32 format
      uint32_t bits = 0;
      std::memcpy(&bits, &params[i], sizeof bits);
      for (int b = 0; b < 4; ++b) msg.data._buffer[4 + 4 * i + b] = static_cast<uint8_t>(bits >> (8 * b));
    }
    write("ros_compressed_image_cdr", "compressed-depth-32FC1-rvl", cdr(msg));
  }
  write("ros_geometry_cdr", "camera-info",
        withSelector(0, cdr(wire::cameraInfoFromIntrinsics(frame.intrinsics, stamp, "cam").msg())));
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 0, 1)).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(1, 2, 3);
  auto transform = wire::transformFromPose(pose, stamp, "world", "cam");
  write("ros_geometry_cdr", "transform", withSelector(1, cdr(transform.msg())));
  wire::OwnedMessage<tf2_msgs_msg_dds__TFMessage_> tf;
  tf.keepSequence(tf.msg().transforms,
                  std::vector<geometry_msgs_msg_dds__TransformStamped_>{transform.msg(), transform.msg()});
  write("ros_geometry_cdr", "tf-message", withSelector(2, cdr(tf.msg())));
}

// Requests as the client library encodes them.
template <class Codec>
Bytes requestCdr(const typename Codec::Request& request) {
  dds::Sample<typename Codec::WireRequest> wire_request;
  Codec::encodeRequest(request, *wire_request);
  return cdr(*wire_request);
}

void serviceSeeds() {
  const RaycastRequest raycast{Pose::Identity(), {32, 24, 20.0, 20.0, 15.5, 11.5}, kAllLayers, 4.0f};
  write("service_requests", "raycast", withSelector(0, requestCdr<wire::RaycastCodec>(raycast)));
  const LabelsAtRequest labels_at{{{0, 0, 1.0}, {-0.3, 0.1, 1.0}, {0.3, 0, 1.5}, {0, 0, 0.5}}};
  write("service_requests", "labels-at", withSelector(1, requestCdr<wire::LabelsAtCodec>(labels_at)));
  const Box region{{-1, -1, 0.5}, {1, 1, 2}};
  write("service_requests", "region", withSelector(2, requestCdr<wire::RegionCodec>(region)));
  ObjectsRequest objects;
  objects.min_voxels = 1;
  write("service_requests", "objects-all", withSelector(3, requestCdr<wire::ObjectsCodec>(objects)));
  objects.label = 5;
  write("service_requests", "objects-5", withSelector(3, requestCdr<wire::ObjectsCodec>(objects)));
  write("service_requests", "mesh", withSelector(4, requestCdr<wire::MeshCodec>({})));
  const Box box{{-0.5, -0.5, 0.5}, {0.5, 0.5, 1.2}};
  write("service_requests", "mesh-box", withSelector(4, requestCdr<wire::MeshCodec>({box, 0, 0})));
  write("service_requests", "distance",
        withSelector(5, requestCdr<wire::DistanceCodec>({{{0, 0, 0.9}, {-0.3, 0.1, 1.0}, {0, 0, 3.0}}})));
  OccupancySliceRequest slice;
  slice.z_min = -0.5;
  slice.z_max = 0.5;
  slice.inflation_radius = 0.1;
  write("service_requests", "occupancy-slice", withSelector(6, requestCdr<wire::OccupancySliceCodec>(slice)));
  write("service_requests", "semantic-distance",
        withSelector(7, requestCdr<wire::SemanticDistanceCodec>({{5, 9}, {{0, 0, 0.5}, {0.2, 0, 0.8}}})));
  write("service_requests", "semantic-slice",
        withSelector(8, requestCdr<wire::SemanticSliceCodec>({{5}, 0.0, {-0.5, -0.5}, {0.5, 0.5}, 0.1})));
  write("service_requests", "segment-check",
        withSelector(9, requestCdr<wire::SegmentCheckCodec>(
                            {{{{0, 0, 0.5}, {0, 0, 2.0}}, {{-0.4, 0, 0.8}, {0.4, 0, 0.8}}}, 0.05})));
}

void mapSeeds() {
  const fs::path path = g_out / "map_file" / "seed-tiny.vdb";
  fs::create_directories(path.parent_path());
  // 4x3 pixels: a few leaves, so the file stays a few kB (the fuzzers cap inputs at 64 kB).
  const volume::LabeledVolume map = fuzz::makeTinyMap(4);
  if (Status s = volume::saveMap(map, *builtinLegend("voc"), path, {{"note", "fuzz seed"}}); !s) {
    throw std::runtime_error(s.error());
  }
}

void meshPlySeeds() {
  // The server's mesh of the tiny map, with and without normals, and two hand-made triangles.
  const auto toBytes = [](const std::string& ply) { return Bytes(ply.begin(), ply.end()); };
  auto mesh = render::extractMesh(fuzz::makeTinyMap(8));
  if (!mesh) throw std::runtime_error(mesh.error());
  render::PlyOptions options;
  write("mesh_ply", "tiny-map", toBytes(render::plyBytes(mesh.value(), *builtinLegend("voc"), options).value()));
  options.normals = false;
  write("mesh_ply", "tiny-map-no-normals",
        toBytes(render::plyBytes(mesh.value(), *builtinLegend("voc"), options).value()));
  render::LabeledMesh two;
  two.vertices = {{0.F, 0.F, 1.F}, {1.F, 0.F, 1.F}, {0.F, 1.F, 1.F}, {1.F, 1.F, 1.F}};
  two.normals.assign(4, {0.F, 0.F, -1.F});
  two.labels = {1, 1, 2, 2};
  two.scores = {1.F, 2.F, 3.F, 4.F};
  two.triangles = {{0, 1, 2}, {1, 3, 2}};
  write("mesh_ply", "two-triangles", toBytes(render::plyBytes(two, *builtinLegend("voc")).value()));
}

void textSeeds() {
  writeText("legend_yaml", "small.yaml",
            "name: kitchen\nlabels:\n  - {id: 0, name: unlabeled, color: [0, 0, 0]}\n"
            "  - {id: 1, name: wall, color: [120, 120, 120]}\n  - {id: 7, name: cup}\nbackground: [0]\n");
  writeText(
      "legend_yaml", "block.yaml",
      "name: \"quoted name\"\nlabels:\n  - id: 3\n    name: table\n    color:\n      - 1\n      - 2\n      - 3\n");
  writeText("server_config_yaml", "full.yaml",
            "domain-id: 3\nserver-id: lab\nvoxel-size: 0.02\ntruncation: 0.08\nmax-weight: 100\n"
            "max-label-score: 16\nmin-depth: 0.2\nmax-depth: 4\ncolor: false\nlegend: voc\n"
            "background-labels: [0, 1]\nmap: map.vdb\nautosave-period: 10\nqueue-per-camera: 2\n"
            "history-frames: 30\nhistory-megabytes: 64\npending-segmentations: 8\npending-timeout: 2.5\n"
            "refine-poses: true\nmax-raycast-pixels: 10000\nmesh-chunk-bytes: 65536\nstatus-period: 0.5\n"
            "stale-after: 2\nlog-level: debug\n");
  writeText("server_config_yaml", "empty.yaml", "");
  writeText("server_config_yaml", "comment.yaml", "# only a comment\nvoxel-size: 0.05 # 5 cm\n");
  writeText("seven_scenes_files", "intrinsics.txt", std::string(1, '\0') + "585 0 320\n0 585 240\n0 0 1\n");
  writeText("seven_scenes_files", "pose.txt",
            std::string(1, '\1') +
                "9.9935108e-001\t1.3017e-003\t-3.5993e-002\t1.0e-001\n-2.6167e-003\t9.9925e-001\t-3.8528e-002\t"
                "2.0e-002\n3.5921e-002\t3.8594e-002\t9.9861e-001\t-1.5e-001\n0 0 0 1\n");
  writeText("tum_lists", "three-files.txt",
            "# depth maps\n# file: 'rgbd_dataset_freiburg1_xyz.bag'\n# timestamp filename\n"
            "1305031102.160407 depth/1305031102.160407.png\n1305031102.194330 depth/1305031102.194330.png\n"
            "\n=====\n# color images\n1305031102.175304 rgb/1305031102.175304.png\n"
            "1305031102.211214 rgb/1305031102.211214.png\n"
            "\n=====\n# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n"
            "1305031102.1758 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
            "1305031102.1858 1.3303 0.6256 1.6464 0.6579 0.6161 -0.2932 -0.3189\n");
  writeText("tum_lists", "no-ground-truth.txt",
            "1.0 depth/a.png\n2.0 depth/b.png\n\n=====\n1.01 rgb/a.png\n2.5 rgb/b.png\n");
}

}  // namespace

// The live mesh: an update of two blocks (one with colour, one removed), a map_blocks request
// resuming after a block, a page of one block.
void mapUpdateSeeds() {
  MeshBlock block;
  block.origin = {8, -16, 0};
  block.revision = 7;
  block.own_vertices = 3;
  block.positions = {0, 0, 0, 4096, 0, 0, 0, 4096, 0};
  block.normals = {0, 0, 127, 0, 0, 127, 0, 0, 127};
  block.labels = {1, 1, 2};
  block.scores = {1.0F, 1.0F, 0.5F};
  block.colors = {10, 20, 30, 40, 50, 60, 70, 80, 90};
  block.triangles = {0, 1, 2};
  MeshBlock removed;
  removed.origin = {0, 0, 8};
  removed.revision = 7;
  MapUpdate update;
  update.header = {42, 7, 0, 30, 0.02};
  update.previous_revision = 5;
  update.blocks = {block, removed};
  write("map_updates_cdr", "update", withSelector(0, cdr(wire::encodeMapUpdate(update).msg())));

  MapBlocksRequest request;
  request.since_revision = 2;
  request.resume_after = BlockOrigin{0, 0, 0};
  request.max_bytes = 200;
  dds::Sample<wire::MapBlocksCodec::WireRequest> wire_request;
  wire::MapBlocksCodec::encodeRequest(request, *wire_request);
  write("map_updates_cdr", "request", withSelector(1, cdr(*wire_request)));

  ServiceReply<MapBlocksPage> reply;
  reply.value.header = update.header;
  reply.value.blocks = {block};
  reply.value.complete = false;
  reply.value.next_after = block.origin;
  dds::Sample<wire::MapBlocksCodec::WireReply> wire_reply;
  wire::MapBlocksCodec::encodeReply(reply, *wire_reply);
  write("map_updates_cdr", "page", withSelector(2, cdr(*wire_reply)));
}

int main(int argc, char** argv) {
  CLI::App app{"fuzz_make_seeds: writes the seed corpus of every semfuse fuzz target"};
  std::string out = "fuzz/corpus";
  app.add_option("--out", out, "corpus folder (one subfolder per target)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  g_out = out;
  const Frame frame = smallFrame();
  frameSeeds(frame);
  imagePayloadSeeds(frame);
  segmentationSeeds();
  clientMessageSeeds();
  rosSeeds(frame);
  serviceSeeds();
  mapSeeds();
  mapUpdateSeeds();
  meshPlySeeds();
  textSeeds();
  std::printf("seeds written under %s\n", out.c_str());
  return 0;
}
