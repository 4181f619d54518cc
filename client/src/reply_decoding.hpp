#pragma once
// Conversions between the generated wire structs and the client's C++ types. Private to the
// client library: users of semfuse::client never see a generated C struct.
//
// Frames, segmentations and legends go through common/wire (the codecs the server uses); what
// is here is only what common/wire does not cover: the raycast reply's images (32FC3 normals
// included), the server status and the chunks of a mesh reply. Replies are checked like any
// other input: a server of another version, or a damaged one, gets an error, never a crash.
#include <cstddef>
#include <cstdint>

#include <opencv2/core/mat.hpp>

#include "semfuse/client/map_client.hpp"
#include "semfuse/client/server_status.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/dds/sample.hpp"

namespace semfuse::client::detail {

// Larger sides than any raycast a server answers (its --max-raycast-pixels is far below 65536^2);
// also keeps every size computation of decodeImage far from overflow.
inline constexpr uint32_t kMaxImageSide = 1u << 16;

// sensor_msgs Image_ -> cv::Mat for the encodings raycast replies use (32FC1, 32FC3, 16UC1,
// 8UC1, rgb8, bgr8); an empty image (layer not requested) gives an empty Mat.
Result<cv::Mat> decodeImage(const sensor_msgs_msg_dds__Image_& image);
// The same, without copying where it can: the Mat takes over the sample's pixel buffer (the
// sample's data sequence is left empty). A raycast reply is 5.5 MB at 640x480 with depth, normals
// and labels; copying it into fresh Mats took ~3.6 ms of each reply in semfuse-bench ingest.
// BGR images and buffers the sample does not own are copied as decodeImage does.
Result<cv::Mat> takeImage(sensor_msgs_msg_dds__Image_& image);

ServerStatus decodeStatus(const semfuse_msg_dds__ServerStatus_& msg);

// The most a mesh reply makes the client reserve before its bytes arrive (beyond it the PLY
// buffer grows with the chunks as they come).
inline constexpr uint64_t kMaxMeshReserveBytes = uint64_t{64} << 20;

// Puts the PLY of a chunked mesh reply back together. Chunk 0 names the mesh (id, chunk count,
// total bytes); every later chunk must come from that mesh, in order, and the bytes must add up
// to the announced total. Sizes in a reply are not trusted for allocations.
class MeshAssembly {
 public:
  // Reply `chunk` (0, 1, ... in order); an error says why it does not belong.
  Status add(const semfuse_srv_dds__Mesh_Response_& reply, uint32_t chunk);
  // Chunks announced by chunk 0 (1 before it arrived).
  uint32_t chunkCount() const { return chunk_count_; }
  uint64_t meshId() const { return mesh_id_; }
  // Bytes the PLY buffer holds room for (for tests: what a reply made the client allocate).
  std::size_t reservedBytes() const { return mesh_.ply.capacity(); }
  // The mesh, once every chunk was added; an error when bytes are missing.
  Result<MeshData> finish() &&;

 private:
  MeshData mesh_;
  uint64_t mesh_id_ = 0;
  uint32_t chunk_count_ = 1;
  uint32_t chunks_added_ = 0;
  uint64_t total_bytes_ = 0;
};

}  // namespace semfuse::client::detail
