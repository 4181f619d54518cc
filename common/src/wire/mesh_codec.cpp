#include "semfuse/wire/service_codecs.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

void MeshCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.use_box = request.box.has_value();
  const Box box = request.box.value_or(Box{});
  out.box_min = detail::toPoint(box.min);
  out.box_max = detail::toPoint(box.max);
  out.mesh_id = request.mesh_id;
  out.chunk_index = request.chunk_index;
  out.object_id = request.object_id;
}

Result<MeshRequest> MeshCodec::decodeRequest(const WireRequest& wire) {
  MeshRequest request;
  if (wire.use_box) request.box = Box{detail::fromPoint(wire.box_min), detail::fromPoint(wire.box_max)};
  request.mesh_id = wire.mesh_id;
  request.chunk_index = wire.chunk_index;
  request.object_id = wire.object_id;
  return request;
}

void MeshCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  const MeshChunk& chunk = reply.value;
  out.mesh_id = chunk.mesh_id;
  out.chunk_index = chunk.chunk_index;
  out.chunk_count = chunk.chunk_count;
  out.total_bytes = chunk.total_bytes;
  out.vertex_count = chunk.vertex_count;
  out.face_count = chunk.face_count;
  dds::setSequence(out.ply, chunk.ply.data(), chunk.ply.size());
}

Result<ServiceReply<MeshChunk>> MeshCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<MeshChunk> {
    if (Status s = validateSequence("mesh ply", wire.ply._length, wire.ply._maximum, wire.ply._buffer); !s)
      return makeError(s.error());
    MeshChunk chunk;
    chunk.mesh_id = wire.mesh_id;
    chunk.chunk_index = wire.chunk_index;
    chunk.chunk_count = wire.chunk_count;
    chunk.total_bytes = wire.total_bytes;
    chunk.vertex_count = wire.vertex_count;
    chunk.face_count = wire.face_count;
    chunk.ply.assign(wire.ply._buffer, wire.ply._buffer + wire.ply._length);
    return chunk;
  });
}

}  // namespace semfuse::wire
