#include "semfuse/wire/distance_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void SemanticDistanceCodec::encodeRequest(const Request& request, WireRequest& out) {
  dds::setSequence(out.labels, request.labels.data(), request.labels.size());
  detail::encodeSequence(out.points, request.points, detail::toPoint);
}

Result<SemanticDistanceRequest> SemanticDistanceCodec::decodeRequest(const WireRequest& wire) {
  auto labels = detail::decodeSequence("semantic_distance labels", wire.labels, [](uint16_t l) { return LabelId{l}; });
  if (!labels) return makeError(labels.error());
  auto points = detail::decodeSequence("semantic_distance points", wire.points, detail::fromPoint);
  if (!points) return makeError(points.error());
  return SemanticDistanceRequest{std::move(labels).value(), std::move(points).value()};
}

void SemanticDistanceCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  detail::encodeSequence(out.samples, reply.value, [](const SemanticSample& s) {
    return semfuse_msg_dds__SemanticSample_{s.found, s.label, s.distance, detail::toVector3(s.direction),
                                            detail::toPoint(s.surface_point)};
  });
}

Result<ServiceReply<std::vector<SemanticSample>>> SemanticDistanceCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] {
    return detail::decodeSequence(
        "semantic_distance samples", wire.samples, [](const semfuse_msg_dds__SemanticSample_& s) {
          return SemanticSample{s.found, s.label, s.distance, detail::fromVector3(s.direction),
                                detail::fromPoint(s.surface_point)};
        });
  });
}

}  // namespace semfuse::wire
