// Fuzz target: what clients decode from the server, chosen by the first byte, serialized CDR
// after it -> CDR decoding -> the client's decoder:
//   0 LabelLegend_     wire::decodeLegend (a decoded legend must pass validateLegend)
//   1 TrackedPose_     wire::decodeTrackedPose
//   2 Raycast_Response_ client::detail::decodeImage on each of its five images
//   3 ServerStatus_    client::detail::decodeStatus
//   4 Mesh_Response_   client::detail::MeshAssembly, the reply taken as chunk 0 and, when it
//                      announces more, again as chunk 1
// Other selector values are ignored.
#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"
#include "reply_decoding.hpp"
#include "semfuse/core/legend_io.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/wire/message_codecs.hpp"

namespace {
namespace detail = semfuse::client::detail;

void raycastReply(const semfuse_srv_dds__Raycast_Response_& reply) {
  for (const auto* image : {&reply.depth, &reply.normals, &reply.labels, &reply.confidence, &reply.color}) {
    auto mat = detail::decodeImage(*image);
    if (!mat) continue;
    // An accepted image is exactly what it declared, and its bytes were in the message.
    const cv::Mat& m = mat.value();
    SEMFUSE_FUZZ_CHECK(m.empty() || (static_cast<uint32_t>(m.cols) == image->width &&
                                     static_cast<uint32_t>(m.rows) == image->height &&
                                     m.total() * m.elemSize() <= image->data._length));
  }
}

void meshReply(const semfuse_srv_dds__Mesh_Response_& reply) {
  detail::MeshAssembly assembly;
  if (!assembly.add(reply, 0)) return;
  if (assembly.chunkCount() > 1 && !assembly.add(reply, 1)) return;
  auto mesh = std::move(assembly).finish();
  if (mesh && reply.total_bytes != 0) SEMFUSE_FUZZ_CHECK(mesh.value().ply.size() == reply.total_bytes);
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t selector = data[0];
  ++data;
  --size;
  namespace dds = semfuse::dds;
  switch (selector) {
    case 0:
      if (auto sample = dds::deserialize<semfuse_msg_dds__LabelLegend_>(data, size)) {
        auto legend = semfuse::wire::decodeLegend(*sample.value());
        if (legend) SEMFUSE_FUZZ_CHECK(semfuse::validateLegend(legend.value()).ok());
      }
      break;
    case 1:
      if (auto sample = dds::deserialize<semfuse_msg_dds__TrackedPose_>(data, size))
        (void)semfuse::wire::decodeTrackedPose(*sample.value());
      break;
    case 2:
      if (auto sample = dds::deserialize<semfuse_srv_dds__Raycast_Response_>(data, size)) raycastReply(*sample.value());
      break;
    case 3:
      if (auto sample = dds::deserialize<semfuse_msg_dds__ServerStatus_>(data, size))
        (void)detail::decodeStatus(*sample.value());
      break;
    case 4:
      if (auto sample = dds::deserialize<semfuse_srv_dds__Mesh_Response_>(data, size)) meshReply(*sample.value());
      break;
    default:
      break;
  }
  return 0;
}
