#include "semfuse/wire/distance_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

static_assert(static_cast<uint8_t>(SegmentStatus::kFree) == semfuse_msg_dds__SegmentResult_Constants_FREE);
static_assert(static_cast<uint8_t>(SegmentStatus::kCollision) == semfuse_msg_dds__SegmentResult_Constants_COLLISION);
static_assert(static_cast<uint8_t>(SegmentStatus::kUnknown) == semfuse_msg_dds__SegmentResult_Constants_UNKNOWN);

void SegmentCheckCodec::encodeRequest(const Request& request, WireRequest& out) {
  detail::encodeSequence(out.segments, request.segments, [](const Segment& s) {
    return semfuse_msg_dds__Segment_{detail::toPoint(s.start), detail::toPoint(s.end)};
  });
  out.radius = request.radius;
}

Result<SegmentCheckRequest> SegmentCheckCodec::decodeRequest(const WireRequest& wire) {
  auto segments =
      detail::decodeSequence("segment_check segments", wire.segments, [](const semfuse_msg_dds__Segment_& s) {
        return Segment{detail::fromPoint(s.start), detail::fromPoint(s.end)};
      });
  if (!segments) return makeError(segments.error());
  return SegmentCheckRequest{std::move(segments).value(), wire.radius};
}

void SegmentCheckCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  detail::encodeSequence(out.results, reply.value, [](const SegmentResult& r) {
    return semfuse_msg_dds__SegmentResult_{static_cast<uint8_t>(r.status), r.fraction, detail::toPoint(r.blocked_at),
                                           r.min_clearance};
  });
}

Result<ServiceReply<std::vector<SegmentResult>>> SegmentCheckCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<Reply> {
    for (uint32_t i = 0; wire.results._buffer && i < wire.results._length; ++i)
      if (wire.results._buffer[i].status > semfuse_msg_dds__SegmentResult_Constants_UNKNOWN)
        return makeError("segment_check result " + std::to_string(i) + ": unknown status " +
                         std::to_string(wire.results._buffer[i].status));
    return detail::decodeSequence("segment_check results", wire.results, [](const semfuse_msg_dds__SegmentResult_& r) {
      return SegmentResult{static_cast<SegmentStatus>(r.status), r.fraction, detail::fromPoint(r.blocked_at),
                           r.min_clearance};
    });
  });
}

}  // namespace semfuse::wire
