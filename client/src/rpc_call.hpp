#pragma once
// Internal: one request/reply round trip of a service codec (common/wire), for MapClient's calls.
#include <string>
#include <type_traits>
#include <utility>

#include "semfuse/client/call_result.hpp"
#include "semfuse/dds/rpc.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/reply_status.hpp"
#include "semfuse/wire/service_codecs.hpp"

namespace semfuse::client {

template <class Codec>
using Rpc = dds::RpcClient<typename Codec::WireRequest, typename Codec::WireReply>;

// RpcClient reports only transport problems as errors (no server matched, no reply in time),
// which are timeouts from the caller's point of view; a reply with a non-OK status is the
// server's error, a reply that does not decode the client's.
template <class Codec>
CallResult<typename Codec::Reply> call(Rpc<Codec>& rpc, const typename Codec::Request& request,
                                       std::chrono::milliseconds timeout) {
  dds::Sample<typename Codec::WireRequest> wire_request;
  Codec::encodeRequest(request, *wire_request);
  auto wire_reply = rpc.call(*wire_request, timeout);
  if (!wire_reply) return {Failure::kTimeout, wire_reply.error()};
  // The raycast's images take over the reply's pixel buffers instead of copying them.
  auto reply = [&] {
    if constexpr (std::is_same_v<Codec, wire::RaycastCodec>) return Codec::takeReply(*wire_reply.value());
    else return Codec::decodeReply(*wire_reply.value());
  }();
  if (!reply) return {Failure::kClient, std::string(Codec::kName) + " reply: " + reply.error()};
  if (!reply.value().ok()) {
    // The server's message, with the error code of its reply status.
    const auto status = static_cast<int32_t>(reply.value().code);
    return {Failure::kServer, makeError(wire::errorCodeOfReplyStatus(status),
                                        "server error " + std::to_string(status) + ": " + reply.value().message)};
  }
  return std::move(reply.value().value);
}

}  // namespace semfuse::client
