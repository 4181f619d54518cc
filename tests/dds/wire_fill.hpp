#pragma once
// Fills every field of every wire type with a distinct value drawn from a counter, so that a
// field lost, swapped or truncated on the way shows up in an exact comparison.
#include <cstdint>
#include <string>
#include <vector>

#include "semfuse/dds/sample.hpp"

namespace semfuse::dds::testing {

class Filler {
 public:
  explicit Filler(uint32_t seed) : next_(seed * 1000u + 1u) {}

  uint32_t u32() { return next_++; }
  int32_t i32() { return -static_cast<int32_t>(next_++); }
  uint64_t u64() { return (uint64_t{next_++} << 33) + 7; }
  int64_t i64() { return -static_cast<int64_t>(u64()); }
  uint16_t u16() { return static_cast<uint16_t>(next_++); }
  uint8_t u8() { return static_cast<uint8_t>(next_++); }
  bool flag() { return (next_++ % 2) == 1; }
  double f64() { return next_++ * 1.25 + 0.0625; }
  float f32() { return static_cast<float>(next_++) * 0.5f + 0.25f; }
  std::string text(const char* what) { return std::string(what) + "-" + std::to_string(next_++); }
  void string(char*& field, const char* what) { setString(field, text(what)); }

  template <class Sequence>
  void bytes(Sequence& seq, std::size_t n) {
    std::vector<uint8_t> v(n);
    for (auto& b : v) b = u8();
    setSequence(seq, v.data(), v.size());
  }
  template <class Sequence>
  void shorts(Sequence& seq, std::size_t n) {
    std::vector<uint16_t> v(n);
    for (auto& x : v) x = u16();
    setSequence(seq, v.data(), v.size());
  }
  template <std::size_t N>
  void doubles(double (&a)[N]) {
    for (auto& x : a) x = f64();
  }

 private:
  uint32_t next_;
};

inline void fill(builtin_interfaces_msg_dds__Time_& m, Filler& f) {
  m.sec = f.i32();
  m.nanosec = f.u32();
}
inline void fill(std_msgs_msg_dds__Header_& m, Filler& f) {
  fill(m.stamp, f);
  f.string(m.frame_id, "frame");
}
inline void fill(geometry_msgs_msg_dds__Vector3_& m, Filler& f) {
  m.x = f.f64();
  m.y = f.f64();
  m.z = f.f64();
}
inline void fill(geometry_msgs_msg_dds__Point_& m, Filler& f) {
  m.x = f.f64();
  m.y = f.f64();
  m.z = f.f64();
}
inline void fill(geometry_msgs_msg_dds__Quaternion_& m, Filler& f) {
  m.x = f.f64();
  m.y = f.f64();
  m.z = f.f64();
  m.w = f.f64();
}
inline void fill(geometry_msgs_msg_dds__Transform_& m, Filler& f) {
  fill(m.translation, f);
  fill(m.rotation, f);
}
inline void fill(geometry_msgs_msg_dds__TransformStamped_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.child_frame_id, "child");
  fill(m.transform, f);
}
inline void fill(sensor_msgs_msg_dds__Image_& m, Filler& f) {
  fill(m.header, f);
  m.height = 3;
  m.width = 5;
  setString(m.encoding, "mono8");
  m.is_bigendian = 0;
  m.step = 5;
  f.bytes(m.data, 15);
}
inline void fill(sensor_msgs_msg_dds__CompressedImage_& m, Filler& f) {
  fill(m.header, f);
  setString(m.format, "png");
  f.bytes(m.data, 33);
}
inline void fill(sensor_msgs_msg_dds__RegionOfInterest_& m, Filler& f) {
  m.x_offset = f.u32();
  m.y_offset = f.u32();
  m.height = f.u32();
  m.width = f.u32();
  m.do_rectify = true;
}
inline void fill(sensor_msgs_msg_dds__CameraInfo_& m, Filler& f) {
  fill(m.header, f);
  m.height = f.u32();
  m.width = f.u32();
  setString(m.distortion_model, "plumb_bob");
  const double d[5] = {f.f64(), f.f64(), f.f64(), f.f64(), f.f64()};
  setSequence(m.d, d, 5);
  f.doubles(m.k);
  f.doubles(m.r);
  f.doubles(m.p);
  m.binning_x = f.u32();
  m.binning_y = f.u32();
  fill(m.roi, f);
}
inline void fill(tf2_msgs_msg_dds__TFMessage_& m, Filler& f) {
  resizeSequence(m.transforms, 3);
  for (uint32_t i = 0; i < 3; ++i) fill(m.transforms._buffer[i], f);
}
inline void fill(semfuse_msg_dds__CameraIntrinsics_& m, Filler& f) {
  m.width = f.u32();
  m.height = f.u32();
  m.fx = f.f64();
  m.fy = f.f64();
  m.cx = f.f64();
  m.cy = f.f64();
}
inline void fill(semfuse_msg_dds__Frame_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.camera_id, "camera");
  m.seq = f.u64();
  fill(m.intrinsics, f);
  setString(m.depth_encoding, "16UC1");
  m.depth_scale = 0.001f;
  f.bytes(m.depth, 2 * 4 * 3);
  setString(m.color_encoding, "rgb8");
  f.bytes(m.color, 3 * 4 * 3);
  m.has_pose = true;
  f.doubles(m.camera_to_world);
}
inline void fill(semfuse_msg_dds__Segmentation_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.camera_id, "camera");
  m.frame_seq = f.u64();
  f.string(m.segmenter_id, "seg");
  m.width = 4;
  m.height = 2;
  f.shorts(m.labels, 8);
  setString(m.confidence_encoding, "8UC1");
  f.bytes(m.confidence, 8);
}
inline void fill(semfuse_msg_dds__TrackedPose_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.camera_id, "camera");
  m.seq = f.u64();
  m.state = 1;
  m.posed = true;
  f.doubles(m.camera_to_world);
  m.inlier_ratio = f.f32();
  m.residual = f.f32();
  m.iterations = f.u32();
  m.track_ms = f.f32();
}
inline void fill(semfuse_msg_dds__Counter_& m, Filler& f) {
  f.string(m.reason, "reason");
  f.string(m.camera_id, "camera");
  m.count = f.u64();
}
inline void fill(semfuse_msg_dds__CameraState_& m, Filler& f) {
  f.string(m.camera_id, "camera");
  m.tracking_state = 2;
  m.last_seq = f.u64();
  m.frames_received = f.u64();
  m.frames_integrated = f.u64();
  m.frames_lost = f.u64();
  m.frame_rate_hz = f.f32();
  m.last_frame_age_s = f.f32();
  m.stale = true;
  f.string(m.lost_reason, "reason");
  m.frames_since_lost = f.u64();
  m.relocalisations = f.u64();
}
inline void fill(semfuse_msg_dds__ErrorEntry_& m, Filler& f) {
  fill(m.stamp, f);
  f.string(m.source, "source");
  f.string(m.message, "message");
}
inline void fill(semfuse_msg_dds__StageTiming_& m, Filler& f) {
  f.string(m.stage, "stage");
  m.count = f.u64();
  m.p50_ms = f.f32();
  m.p95_ms = f.f32();
  m.max_ms = f.f32();
}
template <class Sequence>
void fillEach(Sequence& seq, std::size_t n, Filler& f) {
  resizeSequence(seq, n);
  for (std::size_t i = 0; i < n; ++i) fill(seq._buffer[i], f);
}
inline void fill(semfuse_msg_dds__ServerStatus_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.server_id, "server");
  f.string(m.version, "version");
  m.uptime_s = f.f64();
  m.frames_received = f.u64();
  m.frames_integrated = f.u64();
  m.frames_lost = f.u64();
  m.segmentations_received = f.u64();
  m.segmentations_integrated = f.u64();
  fillEach(m.dropped, 2, f);
  fillEach(m.rejected, 3, f);
  m.queued_frames = f.u32();
  m.pending_segmentations = f.u32();
  m.history_frames = f.u32();
  m.voxel_size = f.f64();
  m.truncation = f.f64();
  m.allocated_voxels = f.u64();
  m.allocated_blocks = f.u64();
  m.map_bytes = f.u64();
  m.rss_bytes = f.u64();
  fillEach(m.cameras, 2, f);
  fillEach(m.last_errors, 2, f);
  f.string(m.map_file, "map");
  m.last_save_ok = true;
  m.last_save_age_s = f.f64();
  fillEach(m.stages, 2, f);
  m.map_revision = f.u64();
  m.distance_field_revision = f.u64();
  m.snapshot_bytes = f.u64();
}
inline void fill(semfuse_msg_dds__LabelEntry_& m, Filler& f) {
  m.id = f.u16();
  f.string(m.name, "label");
  m.r = f.u8();
  m.g = f.u8();
  m.b = f.u8();
}
inline void fill(semfuse_msg_dds__LabelLegend_& m, Filler& f) {
  fill(m.header, f);
  f.string(m.name, "legend");
  fillEach(m.labels, 4, f);
  f.shorts(m.background_ids, 2);
}
inline void fill(semfuse_msg_dds__VoxelSample_& m, Filler& f) {
  m.observed = true;
  m.label = f.u16();
  m.confidence = f.f32();
  m.tsdf = f.f32();
  m.weight = f.f32();
}
inline void fill(semfuse_msg_dds__LabelCount_& m, Filler& f) {
  m.label = f.u16();
  m.surface_voxels = f.u64();
  m.area_m2 = f.f64();
}
inline void fill(semfuse_msg_dds__FrameRef_& m, Filler& f) {
  f.string(m.camera_id, "camera");
  m.seq = f.u64();
}
inline void fill(semfuse_msg_dds__ObjectInstance_& m, Filler& f) {
  m.id = f.u32();
  m.label = f.u16();
  fill(m.bbox_min, f);
  fill(m.bbox_max, f);
  fill(m.centroid, f);
  m.voxel_count = f.u64();
  m.mean_confidence = f.f32();
  m.area_m2 = f.f64();
  fill(m.box_center, f);
  fill(m.box_half_extents, f);
  fill(m.box_rotation, f);
  m.fragment = true;
  fillEach(m.frames, 2, f);
  m.frame_count = f.u32();
}
template <class M>
void fillReplyHeader(M& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  m.status = 2;
  f.string(m.message, "status");
}
inline void fill(semfuse_srv_dds__Raycast_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  f.doubles(m.camera_to_world);
  fill(m.intrinsics, f);
  m.layers = 31;
  m.max_range = f.f32();
}
inline void fill(semfuse_srv_dds__Raycast_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  fill(m.depth, f);
  fill(m.normals, f);
  fill(m.labels, f);
  fill(m.confidence, f);
  fill(m.color, f);
}
inline void fill(semfuse_srv_dds__LabelsAt_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  fillEach(m.points, 3, f);
}
inline void fill(semfuse_srv_dds__LabelsAt_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  fillEach(m.samples, 3, f);
}
inline void fill(semfuse_srv_dds__Region_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  fill(m.min, f);
  fill(m.max, f);
}
inline void fill(semfuse_srv_dds__Region_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  fillEach(m.histogram, 3, f);
  m.observed_voxels = f.u64();
  m.occupied_voxels = f.u64();
  m.free_voxels = f.u64();
  m.occupancy = f.f64();
}
inline void fill(semfuse_srv_dds__Objects_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  m.label = f.u16();
  m.min_voxels = f.u32();
  m.use_near = true;
  fill(m.near, f);
  m.radius = f.f64();
  m.include_fragments = true;
  m.max_age = f.f64();
}
inline void fill(semfuse_srv_dds__Objects_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  fillEach(m.objects, 2, f);
}
inline void fill(semfuse_srv_dds__Mesh_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  m.use_box = true;
  fill(m.box_min, f);
  fill(m.box_max, f);
  m.mesh_id = f.u64();
  m.chunk_index = f.u32();
  m.object_id = f.u32();
}
inline void fill(semfuse_srv_dds__Mesh_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  m.mesh_id = f.u64();
  m.chunk_index = f.u32();
  m.chunk_count = f.u32();
  m.total_bytes = f.u64();
  m.vertex_count = f.u32();
  m.face_count = f.u32();
  f.bytes(m.ply, 41);
}
inline void fill(semfuse_srv_dds__Admin_Request_& m, Filler& f) {
  m.client_guid_ = f.u64();
  m.sequence_number_ = f.i64();
  m.command = 2;
  f.string(m.path, "path");
}
inline void fill(semfuse_srv_dds__Admin_Response_& m, Filler& f) {
  fillReplyHeader(m, f);
  fill(m.server_status, f);
}

template <class T>
Sample<T> filledSample(uint32_t seed) {
  Sample<T> sample;
  Filler filler(seed);
  fill(*sample, filler);
  return sample;
}

}  // namespace semfuse::dds::testing
