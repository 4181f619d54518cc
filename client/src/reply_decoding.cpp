#include "reply_decoding.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include <dds/dds.h>
#include <opencv2/imgproc.hpp>

namespace semfuse::client::detail {
namespace {
std::string str(const char* s) { return s ? std::string(s) : std::string(); }
}  // namespace

namespace {

// What decodeImage and takeImage check before touching the pixels.
struct ImageLayout {
  int type = -1;
  int rows = 0, cols = 0;
  uint64_t row_bytes = 0, step = 0;
  bool bgr = false;
};

Result<ImageLayout> imageLayout(const sensor_msgs_msg_dds__Image_& image) {
  if (image.width > kMaxImageSide || image.height > kMaxImageSide)
    return makeError("image of " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                     " pixels exceeds " + std::to_string(kMaxImageSide) + " a side");
  const std::string encoding = str(image.encoding);
  ImageLayout layout;
  if (encoding == "32FC1") layout.type = CV_32FC1;
  else if (encoding == "32FC3") layout.type = CV_32FC3;
  else if (encoding == "16UC1" || encoding == "mono16") layout.type = CV_16UC1;
  else if (encoding == "8UC1" || encoding == "mono8") layout.type = CV_8UC1;
  else if (encoding == "rgb8" || encoding == "bgr8" || encoding == "8UC3") layout.type = CV_8UC3;
  else return makeError("unsupported image encoding '" + encoding + "'");
  if (image.is_bigendian && CV_ELEM_SIZE1(layout.type) > 1) return makeError("big-endian images are not supported");
  layout.bgr = encoding == "bgr8";
  layout.rows = static_cast<int>(image.height);
  layout.cols = static_cast<int>(image.width);
  layout.row_bytes = static_cast<uint64_t>(layout.cols) * CV_ELEM_SIZE(layout.type);
  layout.step = image.step == 0 ? layout.row_bytes : image.step;
  if (layout.step < layout.row_bytes ||
      image.data._length < layout.step * static_cast<uint64_t>(layout.rows - 1) + layout.row_bytes) {
    return makeError("image data shorter than its " + std::to_string(layout.cols) + "x" + std::to_string(layout.rows) +
                     " size");
  }
  return layout;
}

// cv::Mat storage that Cyclone DDS allocated: the pixel buffer of a received sample (dds_alloc),
// handed to the Mat instead of copied, and given back with dds_free when the last Mat that shares
// it lets go. OpenCV's own pattern for foreign buffers (its Python bindings adopt numpy arrays so).
// What a Mat holding such a buffer allocates later (create() to another size) comes from OpenCV's
// default allocator, and is freed by it.
class DdsBufferAllocator final : public cv::MatAllocator {
 public:
  cv::UMatData* allocate(int dims, const int* sizes, int type, void* data, size_t* step, cv::AccessFlag flags,
                         cv::UMatUsageFlags usage) const override {
    return cv::Mat::getDefaultAllocator()->allocate(dims, sizes, type, data, step, flags, usage);
  }
  bool allocate(cv::UMatData* data, cv::AccessFlag flags, cv::UMatUsageFlags usage) const override {
    return cv::Mat::getDefaultAllocator()->allocate(data, flags, usage);
  }
  void deallocate(cv::UMatData* data) const override {
    if (!data) return;
    dds_free(data->origdata);
    delete data;
  }
};

DdsBufferAllocator& ddsBufferAllocator() {
  static DdsBufferAllocator allocator;
  return allocator;
}

// The pixels of a checked image, copied row by row into a new Mat (BGR swapped to RGB).
cv::Mat copyImage(const sensor_msgs_msg_dds__Image_& image, const ImageLayout& l) {
  cv::Mat mat(l.rows, l.cols, l.type);
  for (int r = 0; r < l.rows; ++r)
    std::memcpy(mat.ptr(r), image.data._buffer + r * l.step, static_cast<std::size_t>(l.row_bytes));
  if (l.bgr) cv::cvtColor(mat, mat, cv::COLOR_BGR2RGB);
  return mat;
}

}  // namespace

Result<cv::Mat> decodeImage(const sensor_msgs_msg_dds__Image_& image) {
  if (image.width == 0 || image.height == 0) return cv::Mat();
  auto layout = imageLayout(image);
  if (!layout) return makeError(layout.error());
  return copyImage(image, layout.value());
}

Result<cv::Mat> takeImage(sensor_msgs_msg_dds__Image_& image) {
  if (image.width == 0 || image.height == 0) return cv::Mat();
  auto layout = imageLayout(image);
  if (!layout) return makeError(layout.error());
  const ImageLayout& l = layout.value();
  // A buffer the sample does not own, or BGR (swapped into a new Mat anyway), is copied.
  if (!image.data._release || l.bgr) return copyImage(image, l);
  uint8_t* pixels = image.data._buffer;
  cv::Mat mat(l.rows, l.cols, l.type, pixels, static_cast<std::size_t>(l.step));
  auto* storage = new cv::UMatData(&ddsBufferAllocator());
  storage->data = storage->origdata = pixels;
  storage->size = image.data._length;
  storage->refcount = 1;  // this Mat's reference, as Mat::create leaves it
  mat.u = storage;
  mat.allocator = &ddsBufferAllocator();
  // The sample no longer owns the pixels: freeing it leaves them to the Mat.
  image.data._buffer = nullptr;
  image.data._length = image.data._maximum = 0;
  image.data._release = false;
  return mat;
}

namespace {
std::vector<ReasonCount> counters(const dds_sequence_semfuse_msg_dds__Counter_& seq) {
  std::vector<ReasonCount> out;
  for (uint32_t i = 0; i < seq._length; ++i) {
    out.push_back({str(seq._buffer[i].reason), str(seq._buffer[i].camera_id), seq._buffer[i].count});
  }
  return out;
}
}  // namespace

ServerStatus decodeStatus(const semfuse_msg_dds__ServerStatus_& msg) {
  ServerStatus s;
  s.server_id = str(msg.server_id);
  s.version = str(msg.version);
  s.uptime_s = msg.uptime_s;
  s.frames_received = msg.frames_received;
  s.frames_integrated = msg.frames_integrated;
  s.frames_lost = msg.frames_lost;
  s.segmentations_received = msg.segmentations_received;
  s.segmentations_integrated = msg.segmentations_integrated;
  s.dropped = counters(msg.dropped);
  s.rejected = counters(msg.rejected);
  s.queued_frames = msg.queued_frames;
  s.pending_segmentations = msg.pending_segmentations;
  s.history_frames = msg.history_frames;
  s.voxel_size = msg.voxel_size;
  s.truncation = msg.truncation;
  s.allocated_voxels = msg.allocated_voxels;
  s.allocated_blocks = msg.allocated_blocks;
  s.map_bytes = msg.map_bytes;
  s.rss_bytes = msg.rss_bytes;
  for (uint32_t i = 0; i < msg.cameras._length; ++i) {
    const auto& c = msg.cameras._buffer[i];
    s.cameras.push_back({str(c.camera_id), c.tracking_state, c.last_seq, c.frames_received, c.frames_integrated,
                         c.frames_lost, c.frame_rate_hz, c.last_frame_age_s, c.stale});
  }
  for (uint32_t i = 0; i < msg.last_errors._length; ++i) {
    const auto& e = msg.last_errors._buffer[i];
    s.last_errors.push_back({e.stamp.sec + e.stamp.nanosec * 1e-9, str(e.source), str(e.message)});
  }
  s.map_file = str(msg.map_file);
  s.last_save_ok = msg.last_save_ok;
  s.last_save_age_s = msg.last_save_age_s;
  return s;
}

Status MeshAssembly::add(const semfuse_srv_dds__Mesh_Response_& reply, uint32_t chunk) {
  if (chunk != chunks_added_)
    return makeError("mesh chunk " + std::to_string(chunk) + " added after " + std::to_string(chunks_added_) +
                     " chunks (they go in order)");
  if (chunk == 0) {
    // The first reply names the mesh that later chunks must come from.
    mesh_id_ = reply.mesh_id;
    chunk_count_ = std::max<uint32_t>(1, reply.chunk_count);
    total_bytes_ = reply.total_bytes;
    mesh_.vertex_count = reply.vertex_count;
    mesh_.face_count = reply.face_count;
    // Reserve what was announced, up to what can be trusted before the bytes arrive: the server
    // cuts equal chunks but the last (so never more than chunk_count x the first), and a count
    // near 2^32 with a total to match must not make the client allocate gigabytes up front.
    const uint64_t possible = static_cast<uint64_t>(chunk_count_) * reply.ply._length;
    mesh_.ply.reserve(static_cast<std::size_t>(std::min({total_bytes_, possible, kMaxMeshReserveBytes})));
  } else if (chunk >= chunk_count_) {
    return makeError("mesh chunk " + std::to_string(chunk) + " beyond the " + std::to_string(chunk_count_) +
                     " chunks announced");
  } else if (reply.mesh_id != mesh_id_ || reply.chunk_index != chunk) {
    return makeError("mesh reply for chunk " + std::to_string(reply.chunk_index) + " of mesh " +
                     std::to_string(reply.mesh_id) + ", expected chunk " + std::to_string(chunk) + " of mesh " +
                     std::to_string(mesh_id_));
  }
  if (total_bytes_ != 0 && mesh_.ply.size() + reply.ply._length > total_bytes_)
    return makeError("mesh chunks hold more than the " + std::to_string(total_bytes_) + " bytes announced");
  mesh_.ply.insert(mesh_.ply.end(), reply.ply._buffer, reply.ply._buffer + reply.ply._length);
  ++chunks_added_;
  return Status::Ok();
}

Result<MeshData> MeshAssembly::finish() && {
  if (chunks_added_ != chunk_count_)
    return makeError("mesh has " + std::to_string(chunks_added_) + " of " + std::to_string(chunk_count_) + " chunks");
  if (total_bytes_ != 0 && mesh_.ply.size() != total_bytes_)
    return makeError("mesh has " + std::to_string(mesh_.ply.size()) + " bytes, server announced " +
                     std::to_string(total_bytes_));
  return std::move(mesh_);
}

}  // namespace semfuse::client::detail
