// Fuzz target: what clients decode from the server, chosen by the first byte, serialized CDR
// after it -> CDR decoding -> the decoder the client library uses:
//   0 LabelLegend_      wire::decodeLegend (a decoded legend must pass validateLegend)
//   1 TrackedPose_      wire::decodeTrackedPose
//   2 Raycast_Response_ wire::RaycastCodec::decodeReply and takeReply (the five images)
//   3 ServerStatus_     wire::decodeServerStatus
//   4 Mesh_Response_    wire::MeshCodec::decodeReply, then client::detail::MeshAssembly: the chunk
//                       taken as chunk 0 and, when it announces more, again as chunk 1
//   5 ObjectEvents_     wire::decodeObjectEvents (every accepted event of a known kind)
// Other selector values are ignored.
#include <cstddef>
#include <cstdint>
#include <utility>

#include "fuzz_support.hpp"
#include "mesh_assembly.hpp"
#include "semfuse/core/legend_io.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/message_codecs.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "semfuse/wire/status_codec.hpp"

namespace {
using namespace semfuse;
namespace detail = semfuse::client::detail;

// An accepted image is exactly what it declared, and its bytes were in the message.
void checkImage(const cv::Mat& m, const sensor_msgs_msg_dds__Image_& image, uint32_t length) {
  SEMFUSE_FUZZ_CHECK(m.empty() ||
                     (static_cast<uint32_t>(m.cols) == image.width && static_cast<uint32_t>(m.rows) == image.height &&
                      m.total() * m.elemSize() <= length));
}

void raycastReply(semfuse_srv_dds__Raycast_Response_& reply) {
  auto decoded = wire::RaycastCodec::decodeReply(reply);
  if (!decoded || !decoded.value().ok()) return;
  const RaycastImages& images = decoded.value().value;
  checkImage(images.depth, reply.depth, reply.depth.data._length);
  checkImage(images.normals, reply.normals, reply.normals.data._length);
  checkImage(images.labels, reply.labels, reply.labels.data._length);
  checkImage(images.confidence, reply.confidence, reply.confidence.data._length);
  checkImage(images.color, reply.color, reply.color.data._length);
  // Taking the buffers gives the same images.
  auto taken = wire::RaycastCodec::takeReply(reply);
  SEMFUSE_FUZZ_CHECK(taken.ok());
  SEMFUSE_FUZZ_CHECK(taken.value().value.labels.size() == images.labels.size());
}

void meshReply(const semfuse_srv_dds__Mesh_Response_& reply) {
  auto decoded = wire::MeshCodec::decodeReply(reply);
  if (!decoded || !decoded.value().ok()) return;
  const MeshChunk& chunk = decoded.value().value;
  detail::MeshAssembly assembly;
  if (!assembly.add(chunk, 0)) return;
  if (assembly.chunkCount() > 1 && !assembly.add(chunk, 1)) return;
  auto mesh = std::move(assembly).finish();
  if (mesh && reply.total_bytes != 0) SEMFUSE_FUZZ_CHECK(mesh.value().ply.size() == reply.total_bytes);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  ++data;
  --size;
  switch (selector) {
    case 0:
      if (auto sample = dds::deserialize<semfuse_msg_dds__LabelLegend_>(data, size)) {
        auto legend = wire::decodeLegend(*sample.value());
        if (legend) SEMFUSE_FUZZ_CHECK(validateLegend(legend.value()).ok());
      }
      break;
    case 1:
      if (auto sample = dds::deserialize<semfuse_msg_dds__TrackedPose_>(data, size))
        (void)wire::decodeTrackedPose(*sample.value());
      break;
    case 2:
      if (auto sample = dds::deserialize<semfuse_srv_dds__Raycast_Response_>(data, size)) raycastReply(*sample.value());
      break;
    case 3:
      if (auto sample = dds::deserialize<semfuse_msg_dds__ServerStatus_>(data, size))
        (void)wire::decodeServerStatus(*sample.value());
      break;
    case 4:
      if (auto sample = dds::deserialize<semfuse_srv_dds__Mesh_Response_>(data, size)) meshReply(*sample.value());
      break;
    case 5:
      if (auto sample = dds::deserialize<semfuse_msg_dds__ObjectEvents_>(data, size)) {
        auto events = wire::decodeObjectEvents(*sample.value());
        if (events) {
          for (const ObjectEvent& event : events.value().events)
            SEMFUSE_FUZZ_CHECK(event.kind <= ObjectEventKind::kVanished);
        }
      }
      break;
    default:
      break;
  }
  return 0;
}
