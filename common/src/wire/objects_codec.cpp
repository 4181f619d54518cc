#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void ObjectsCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.label = request.label;
  out.min_voxels = request.min_voxels;
}

Result<ObjectsRequest> ObjectsCodec::decodeRequest(const WireRequest& wire) {
  ObjectsRequest request;
  request.label = wire.label;
  request.min_voxels = wire.min_voxels;
  return request;
}

void ObjectsCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  detail::encodeSequence(out.objects, reply.value, [](const ObjectInstance& o) {
    semfuse_msg_dds__ObjectInstance_ wire{};
    wire.id = o.id;
    wire.label = o.label;
    wire.bbox_min = detail::toPoint(o.bbox_min);
    wire.bbox_max = detail::toPoint(o.bbox_max);
    wire.centroid = detail::toPoint(o.centroid);
    wire.voxel_count = o.voxel_count;
    wire.mean_confidence = o.mean_confidence;
    return wire;
  });
}

Result<ServiceReply<std::vector<ObjectInstance>>> ObjectsCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] {
    return detail::decodeSequence("objects", wire.objects, [](const semfuse_msg_dds__ObjectInstance_& o) {
      ObjectInstance instance;
      instance.id = o.id;
      instance.label = o.label;
      instance.bbox_min = detail::fromPoint(o.bbox_min);
      instance.bbox_max = detail::fromPoint(o.bbox_max);
      instance.centroid = detail::fromPoint(o.centroid);
      instance.voxel_count = o.voxel_count;
      instance.mean_confidence = o.mean_confidence;
      return instance;
    });
  });
}

}  // namespace semfuse::wire
