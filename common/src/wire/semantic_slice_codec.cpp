#include <string>

#include "semfuse/wire/distance_codecs.hpp"
#include "semfuse/wire/image_message.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void SemanticSliceCodec::encodeRequest(const Request& request, WireRequest& out) {
  dds::setSequence(out.labels, request.labels.data(), request.labels.size());
  out.z = request.z;
  out.min_x = request.min.x();
  out.min_y = request.min.y();
  out.max_x = request.max.x();
  out.max_y = request.max.y();
  out.resolution = request.resolution;
}

Result<SemanticSliceRequest> SemanticSliceCodec::decodeRequest(const WireRequest& wire) {
  auto labels = detail::decodeSequence("semantic_slice labels", wire.labels, [](uint16_t l) { return LabelId{l}; });
  if (!labels) return makeError(labels.error());
  SemanticSliceRequest request;
  request.labels = std::move(labels).value();
  request.z = wire.z;
  request.min = {wire.min_x, wire.min_y};
  request.max = {wire.max_x, wire.max_y};
  request.resolution = wire.resolution;
  return request;
}

void SemanticSliceCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  out.min_x = reply.value.min.x();
  out.min_y = reply.value.min.y();
  out.resolution = reply.value.resolution;
  out.z = reply.value.z;
  fillImageMessage(out.distance, reply.value.distance, "32FC1", "map");
}

Result<ServiceReply<SemanticSlice>> SemanticSliceCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<SemanticSlice> {
    auto image = decodeImageMessage(wire.distance);
    if (!image) return makeError("semantic_slice distance: " + image.error());
    if (!image.value().empty() && image.value().type() != CV_32FC1)
      return makeError("semantic_slice distance: " + typeName(image.value().type()) + " image, expected 32FC1");
    SemanticSlice slice;
    slice.min = {wire.min_x, wire.min_y};
    slice.resolution = wire.resolution;
    slice.z = wire.z;
    slice.distance = std::move(image).value();
    return slice;
  });
}

}  // namespace semfuse::wire
