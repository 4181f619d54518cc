#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

#include "semfuse/wire/map_update_codecs.hpp"
#include "semfuse/wire/ros_codec.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {
namespace {

std::string originText(const BlockOrigin& o) {
  return "(" + std::to_string(o[0]) + ", " + std::to_string(o[1]) + ", " + std::to_string(o[2]) + ")";
}

// A sequence's elements copied into a vector, after checking that it holds what it declares.
template <class Element, class Sequence>
Result<std::vector<Element>> copySequence(const std::string& what, const Sequence& seq) {
  static_assert(sizeof(*seq._buffer) == sizeof(Element));
  if (Status s = validateSequence(what, seq._length, seq._maximum, seq._buffer); !s) return makeError(s.error());
  std::vector<Element> out(seq._length);
  if (seq._length > 0) std::memcpy(out.data(), seq._buffer, seq._length * sizeof(Element));
  return out;
}

// Points a generated sequence at a vector's elements without copying (Cyclone never frees them).
template <class Sequence, class Element>
void borrowSequence(Sequence& seq, const std::vector<Element>& elements) {
  static_assert(sizeof(*seq._buffer) == sizeof(Element));
  seq._maximum = seq._length = static_cast<uint32_t>(elements.size());
  // The generated struct's pointer is not const; the writer only reads through it.
  seq._buffer = elements.empty()
                    ? nullptr
                    : const_cast<std::remove_pointer_t<decltype(seq._buffer)>*>(  // NOLINT
                          reinterpret_cast<const std::remove_pointer_t<decltype(seq._buffer)>*>(elements.data()));
  seq._release = false;
}

void fillBlock(semfuse_msg_dds__MeshBlock_& out, const MeshBlock& block, bool borrow) {
  for (int axis = 0; axis < 3; ++axis) out.origin[axis] = block.origin[axis];
  out.revision = block.revision;
  out.own_vertices = block.own_vertices;
  if (borrow) {
    borrowSequence(out.positions, block.positions);
    borrowSequence(out.normals, block.normals);
    borrowSequence(out.labels, block.labels);
    borrowSequence(out.scores, block.scores);
    borrowSequence(out.colors, block.colors);
    borrowSequence(out.triangles, block.triangles);
  } else {
    dds::setSequence(out.positions, block.positions.data(), block.positions.size());
    dds::setSequence(out.normals, block.normals.data(), block.normals.size());
    dds::setSequence(out.labels, block.labels.data(), block.labels.size());
    dds::setSequence(out.scores, block.scores.data(), block.scores.size());
    dds::setSequence(out.colors, block.colors.data(), block.colors.size());
    dds::setSequence(out.triangles, block.triangles.data(), block.triangles.size());
  }
}

template <class Sequence>
Result<std::vector<MeshBlock>> decodeBlocks(const Sequence& blocks) {
  if (Status s = validateSequence("blocks", blocks._length, blocks._maximum, blocks._buffer); !s)
    return makeError(s.error());
  std::vector<MeshBlock> out;
  out.reserve(blocks._length);
  for (uint32_t i = 0; i < blocks._length; ++i) {
    auto block = decodeMeshBlock(blocks._buffer[i]);
    if (!block) return makeError("block " + std::to_string(i) + ": " + block.error());
    out.push_back(std::move(block).value());
  }
  return out;
}

}  // namespace

Status validateMeshBlock(const MeshBlock& block) {
  const std::string where = "mesh block " + originText(block.origin);
  for (int axis = 0; axis < 3; ++axis)
    if (block.origin[axis] % MeshBlock::kBlockVoxels != 0)
      return makeError(where + ": origin is not a multiple of " + std::to_string(MeshBlock::kBlockVoxels));
  const std::size_t n = block.labels.size();
  if (n > std::size_t{std::numeric_limits<uint16_t>::max()} + 1)
    return makeError(where + ": " + std::to_string(n) + " vertices, at most 65536");
  auto expect = [&](const char* what, std::size_t got, std::size_t want) -> Status {
    if (got == want) return Status::Ok();
    return makeError(where + ": " + what + " has " + std::to_string(got) + " values for " + std::to_string(n) +
                     " vertices, expected " + std::to_string(want));
  };
  if (Status s = expect("positions", block.positions.size(), 3 * n); !s) return s;
  if (Status s = expect("normals", block.normals.size(), 3 * n); !s) return s;
  if (Status s = expect("scores", block.scores.size(), n); !s) return s;
  // A NaN or infinite score would reach a follower's viewer page as invalid JSON.
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(block.scores[i]))
      return makeError(where + ": vertex " + std::to_string(i) + " has a score that is not a finite number");
  if (!block.colors.empty())
    if (Status s = expect("colors", block.colors.size(), 3 * n); !s) return s;
  if (block.own_vertices > n)
    return makeError(where + ": " + std::to_string(block.own_vertices) + " own vertices of " + std::to_string(n));
  if (block.triangles.size() % 3 != 0)
    return makeError(where + ": " + std::to_string(block.triangles.size()) + " triangle indices, not a multiple of 3");
  for (std::size_t i = 0; i < block.triangles.size(); ++i)
    if (block.triangles[i] >= n)
      return makeError(where + ": triangle " + std::to_string(i / 3) + " names vertex " +
                       std::to_string(block.triangles[i]) + " of " + std::to_string(n));
  return Status::Ok();
}

Result<MeshBlock> decodeMeshBlock(const semfuse_msg_dds__MeshBlock_& msg) {
  MeshBlock block;
  for (int axis = 0; axis < 3; ++axis) block.origin[axis] = msg.origin[axis];
  block.revision = msg.revision;
  block.own_vertices = msg.own_vertices;
  // Each array after checking that its sequence holds what it declares.
  auto take = [&](auto& field, const auto& seq, const char* what) -> Status {
    using Element = typename std::decay_t<decltype(field)>::value_type;
    auto values = copySequence<Element>(what, seq);
    if (!values) return makeError("mesh block " + originText(block.origin) + ": " + values.error());
    field = std::move(values).value();
    return Status::Ok();
  };
  for (const Status& s :
       {take(block.positions, msg.positions, "positions"), take(block.normals, msg.normals, "normals"),
        take(block.labels, msg.labels, "labels"), take(block.scores, msg.scores, "scores"),
        take(block.colors, msg.colors, "colors"), take(block.triangles, msg.triangles, "triangles")})
    if (!s) return s.errorInfo();
  if (Status s = validateMeshBlock(block); !s) return s.errorInfo();
  return block;
}

EncodedMapUpdate encodeMapUpdate(const MapUpdate& update) {
  EncodedMapUpdate encoded;
  auto& msg = encoded.msg();
  fillHeader(encoded, msg.header, update.stamp, "world");
  msg.session = update.header.session;
  msg.revision = update.header.revision;
  msg.previous_revision = update.previous_revision;
  msg.cleared_revision = update.header.cleared_revision;
  msg.frames_integrated = update.header.frames_integrated;
  msg.voxel_size = update.header.voxel_size;
  msg.part = update.part;
  msg.parts = update.parts;
  std::vector<semfuse_msg_dds__MeshBlock_> blocks(update.blocks.size());
  for (std::size_t i = 0; i < blocks.size(); ++i) fillBlock(blocks[i], update.blocks[i], /*borrow=*/true);
  encoded.keepSequence(msg.blocks, std::move(blocks));
  return encoded;
}

Result<MapUpdate> decodeMapUpdate(const semfuse_msg_dds__MapUpdate_& msg) {
  MapUpdate update;
  update.stamp = stampOf(msg.header);
  update.header.session = msg.session;
  update.header.revision = msg.revision;
  update.header.cleared_revision = msg.cleared_revision;
  update.header.frames_integrated = msg.frames_integrated;
  update.header.voxel_size = msg.voxel_size;
  update.previous_revision = msg.previous_revision;
  update.part = msg.part;
  update.parts = msg.parts;
  if (msg.parts == 0 || msg.part >= msg.parts)
    return makeError("map update: part " + std::to_string(msg.part) + " of " + std::to_string(msg.parts));
  if (!(msg.voxel_size > 0.0)) return makeError("map update: voxel size " + std::to_string(msg.voxel_size));
  auto blocks = decodeBlocks(msg.blocks);
  if (!blocks) return makeError("map update: " + blocks.error());
  update.blocks = std::move(blocks).value();
  return update;
}

void MapBlocksCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.since_revision = request.since_revision;
  out.resume = request.resume_after.has_value();
  const BlockOrigin after = request.resume_after.value_or(BlockOrigin{});
  for (int axis = 0; axis < 3; ++axis) out.resume_after[axis] = after[axis];
  out.max_bytes = request.max_bytes;
}

Result<MapBlocksRequest> MapBlocksCodec::decodeRequest(const WireRequest& wire) {
  MapBlocksRequest request;
  request.since_revision = wire.since_revision;
  if (wire.resume) request.resume_after = BlockOrigin{wire.resume_after[0], wire.resume_after[1], wire.resume_after[2]};
  request.max_bytes = wire.max_bytes;
  return request;
}

void MapBlocksCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  const MapBlocksPage& page = reply.value;
  out.session = page.header.session;
  out.revision = page.header.revision;
  out.cleared_revision = page.header.cleared_revision;
  out.frames_integrated = page.header.frames_integrated;
  out.voxel_size = page.header.voxel_size;
  dds::resizeSequence(out.blocks, page.blocks.size());
  for (std::size_t i = 0; i < page.blocks.size(); ++i) fillBlock(out.blocks._buffer[i], page.blocks[i], false);
  out.complete = page.complete;
  for (int axis = 0; axis < 3; ++axis) out.next_after[axis] = page.next_after[axis];
}

Result<ServiceReply<MapBlocksPage>> MapBlocksCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&]() -> Result<MapBlocksPage> {
    MapBlocksPage page;
    page.header.session = wire.session;
    page.header.revision = wire.revision;
    page.header.cleared_revision = wire.cleared_revision;
    page.header.frames_integrated = wire.frames_integrated;
    page.header.voxel_size = wire.voxel_size;
    auto blocks = decodeBlocks(wire.blocks);
    if (!blocks) return makeError("map_blocks: " + blocks.error());
    page.blocks = std::move(blocks).value();
    page.complete = wire.complete;
    page.next_after = {wire.next_after[0], wire.next_after[1], wire.next_after[2]};
    return page;
  });
}

}  // namespace semfuse::wire
