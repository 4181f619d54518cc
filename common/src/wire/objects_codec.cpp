#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void ObjectsCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.label = request.label;
  out.min_voxels = request.min_voxels;
  out.use_near = request.near.has_value();
  out.near = detail::toPoint(request.near.value_or(Eigen::Vector3d::Zero()));
  out.radius = request.radius;
  out.include_fragments = request.include_fragments;
  out.max_age = request.max_age_s;
}

Result<ObjectsRequest> ObjectsCodec::decodeRequest(const WireRequest& wire) {
  ObjectsRequest request;
  request.label = wire.label;
  request.min_voxels = wire.min_voxels;
  if (wire.use_near) request.near = detail::fromPoint(wire.near);
  request.radius = wire.radius;
  request.include_fragments = wire.include_fragments;
  request.max_age_s = wire.max_age;
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
    wire.area_m2 = o.area_m2;
    wire.box_center = detail::toPoint(o.box_center);
    wire.box_half_extents = {o.box_half_extents.x(), o.box_half_extents.y(), o.box_half_extents.z()};
    wire.box_rotation = {o.box_rotation.x(), o.box_rotation.y(), o.box_rotation.z(), o.box_rotation.w()};
    wire.fragment = o.fragment;
    dds::resizeSequence(wire.frames, o.frames.size());
    for (std::size_t i = 0; i < o.frames.size(); ++i) {
      dds::setString(wire.frames._buffer[i].camera_id, o.frames[i].camera_id);
      wire.frames._buffer[i].seq = o.frames[i].seq;
    }
    wire.frame_count = o.frame_count;
    return wire;
  });
}

Result<ServiceReply<std::vector<ObjectInstance>>> ObjectsCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<Reply> {
    auto objects = detail::decodeSequence("objects", wire.objects, [](const semfuse_msg_dds__ObjectInstance_& o) {
      ObjectInstance instance;
      instance.id = o.id;
      instance.label = o.label;
      instance.bbox_min = detail::fromPoint(o.bbox_min);
      instance.bbox_max = detail::fromPoint(o.bbox_max);
      instance.centroid = detail::fromPoint(o.centroid);
      instance.voxel_count = o.voxel_count;
      instance.mean_confidence = o.mean_confidence;
      instance.area_m2 = o.area_m2;
      instance.box_center = detail::fromPoint(o.box_center);
      instance.box_half_extents = {o.box_half_extents.x, o.box_half_extents.y, o.box_half_extents.z};
      instance.box_rotation =
          Eigen::Quaterniond(o.box_rotation.w, o.box_rotation.x, o.box_rotation.y, o.box_rotation.z);
      instance.fragment = o.fragment;
      instance.frame_count = o.frame_count;
      return instance;
    });
    if (!objects) return objects;
    // The frames, checked like the objects' sequence itself (a peer's reply may declare more
    // than it holds).
    for (uint32_t k = 0; k < wire.objects._length; ++k) {
      auto frames = detail::decodeSequence("object frames", wire.objects._buffer[k].frames,
                                           [](const semfuse_msg_dds__FrameRef_& f) {
                                             return FrameRef{stringOf(f.camera_id), f.seq};
                                           });
      if (!frames) return makeError(frames.error());
      objects.value()[k].frames = std::move(frames).value();
    }
    return objects;
  });
}

}  // namespace semfuse::wire
