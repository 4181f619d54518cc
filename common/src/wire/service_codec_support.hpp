#pragma once
// What the service codecs (service_codecs.hpp) share: the status every reply carries, points,
// and checked sequences.
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <geometry_msgs.h>
#include <srv.h>
#include <Eigen/Core>

#include "semfuse/core/result.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/validation.hpp"

namespace semfuse::wire::detail {

static_assert(static_cast<int32_t>(ReplyCode::kOk) == semfuse_srv_dds__Status_Constants_OK);
static_assert(static_cast<int32_t>(ReplyCode::kInvalidArgument) == semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT);
static_assert(static_cast<int32_t>(ReplyCode::kNotFound) == semfuse_srv_dds__Status_Constants_NOT_FOUND);
static_assert(static_cast<int32_t>(ReplyCode::kUnavailable) == semfuse_srv_dds__Status_Constants_UNAVAILABLE);
static_assert(static_cast<int32_t>(ReplyCode::kInternal) == semfuse_srv_dds__Status_Constants_INTERNAL);
static_assert(static_cast<int32_t>(ReplyCode::kTooLarge) == semfuse_srv_dds__Status_Constants_TOO_LARGE);

template <class T, class WireReply>
void encodeReplyStatus(const ServiceReply<T>& reply, WireReply& out) {
  out.status = static_cast<int32_t>(reply.code);
  dds::setString(out.message, reply.message);
}

// The code and message of `wire`, and its value by `decode_value()` (a Result<T>): see
// service_codecs.hpp for what happens when the value does not decode.
template <class T, class WireReply, class DecodeValue>
Result<ServiceReply<T>> decodeReplyWith(const WireReply& wire, DecodeValue&& decode_value) {
  ServiceReply<T> reply;
  reply.code = static_cast<ReplyCode>(wire.status);  // a code this version does not know stays as it is
  reply.message = stringOf(wire.message);
  Result<T> value = decode_value();
  if (value) {
    reply.value = std::move(value).value();
  } else if (reply.ok()) {
    return makeError(value.error());
  }
  return reply;
}

inline geometry_msgs_msg_dds__Point_ toPoint(const Eigen::Vector3d& p) { return {p.x(), p.y(), p.z()}; }
inline Eigen::Vector3d fromPoint(const geometry_msgs_msg_dds__Point_& p) { return {p.x, p.y, p.z}; }
inline geometry_msgs_msg_dds__Vector3_ toVector3(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }
inline Eigen::Vector3f fromVector3(const geometry_msgs_msg_dds__Vector3_& v) {
  return Eigen::Vector3d(v.x, v.y, v.z).cast<float>();
}

// The elements of a generated sequence, each through `convert`, after checking that the sequence
// holds what it declares.
template <class Sequence, class Convert>
auto decodeSequence(const std::string& what, const Sequence& seq, Convert&& convert)
    -> Result<std::vector<std::decay_t<decltype(convert(*seq._buffer))>>> {
  if (Status s = validateSequence(what, seq._length, seq._maximum, seq._buffer); !s) return makeError(s.error());
  std::vector<std::decay_t<decltype(convert(*seq._buffer))>> out;
  out.reserve(seq._length);
  for (uint32_t i = 0; i < seq._length; ++i) out.push_back(convert(seq._buffer[i]));
  return out;
}

// Fills a generated sequence of plain structs with `items`, each through `convert`.
template <class Sequence, class Item, class Convert>
void encodeSequence(Sequence& seq, const std::vector<Item>& items, Convert&& convert) {
  dds::resizeSequence(seq, items.size());
  for (size_t i = 0; i < items.size(); ++i) seq._buffer[i] = convert(items[i]);
}

}  // namespace semfuse::wire::detail
