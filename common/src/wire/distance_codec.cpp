#include "semfuse/wire/distance_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void DistanceCodec::encodeRequest(const Request& request, WireRequest& out) {
  detail::encodeSequence(out.points, request.points, detail::toPoint);
}

Result<DistanceRequest> DistanceCodec::decodeRequest(const WireRequest& wire) {
  auto points = detail::decodeSequence("distance points", wire.points, detail::fromPoint);
  if (!points) return makeError(points.error());
  return DistanceRequest{std::move(points).value()};
}

void DistanceCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  detail::encodeSequence(out.samples, reply.value, [](const DistanceSample& s) {
    return semfuse_msg_dds__DistanceSample_{s.known, s.beyond, s.distance, detail::toVector3(s.gradient)};
  });
}

Result<ServiceReply<std::vector<DistanceSample>>> DistanceCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] {
    return detail::decodeSequence("distance samples", wire.samples, [](const semfuse_msg_dds__DistanceSample_& s) {
      return DistanceSample{s.known, s.beyond, s.distance, detail::fromVector3(s.gradient)};
    });
  });
}

}  // namespace semfuse::wire
