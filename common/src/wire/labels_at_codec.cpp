#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void LabelsAtCodec::encodeRequest(const Request& request, WireRequest& out) {
  detail::encodeSequence(out.points, request.points, detail::toPoint);
}

Result<LabelsAtRequest> LabelsAtCodec::decodeRequest(const WireRequest& wire) {
  auto points = detail::decodeSequence("labels_at points", wire.points, detail::fromPoint);
  if (!points) return makeError(points.error());
  return LabelsAtRequest{std::move(points).value()};
}

void LabelsAtCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  detail::encodeSequence(out.samples, reply.value, [](const VoxelSample& s) {
    return semfuse_msg_dds__VoxelSample_{s.observed, s.label, s.confidence, s.tsdf, s.weight};
  });
}

Result<ServiceReply<std::vector<VoxelSample>>> LabelsAtCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] {
    return detail::decodeSequence("labels_at samples", wire.samples, [](const semfuse_msg_dds__VoxelSample_& s) {
      return VoxelSample{s.observed, s.label, s.confidence, s.tsdf, s.weight};
    });
  });
}

}  // namespace semfuse::wire
