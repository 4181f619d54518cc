#pragma once
// What the wire tests share: a wire struct as a receiver gets it (serialized to the CDR bytes
// Cyclone puts on the network, then deserialized into a fresh sample), and a service codec's
// request or reply encoded, sent that way and decoded.
#include <gtest/gtest.h>

#include <utility>

#include "semfuse/dds/cdr.hpp"
#include "semfuse/dds/sample.hpp"
#include "semfuse/wire/service_codecs.hpp"

namespace semfuse::wire {

template <class Wire>
dds::Sample<Wire> overTheWire(const Wire& msg) {
  auto received = dds::deserialize<Wire>(dds::serialize(msg));
  if (!received.ok()) ADD_FAILURE() << received.error();
  return received.ok() ? std::move(received).value() : dds::Sample<Wire>();
}

template <class Codec>
typename Codec::Request requestRoundTrip(const typename Codec::Request& in) {
  dds::Sample<typename Codec::WireRequest> sent;
  Codec::encodeRequest(in, *sent);
  auto out = Codec::decodeRequest(*overTheWire(*sent));
  if (!out.ok()) ADD_FAILURE() << Codec::kName << " request: " << out.error();
  return out.ok() ? std::move(out).value() : typename Codec::Request{};
}

template <class Codec>
ServiceReply<typename Codec::Reply> replyRoundTrip(const ServiceReply<typename Codec::Reply>& in) {
  dds::Sample<typename Codec::WireReply> sent;
  Codec::encodeReply(in, *sent);
  auto out = Codec::decodeReply(*overTheWire(*sent));
  if (!out.ok()) ADD_FAILURE() << Codec::kName << " reply: " << out.error();
  return out.ok() ? std::move(out).value() : ServiceReply<typename Codec::Reply>{};
}

template <class T>
ServiceReply<T> okReply(T value) {
  ServiceReply<T> reply;
  reply.value = std::move(value);
  return reply;
}

// A successful reply carrying `value`, over the wire and back.
template <class Codec>
ServiceReply<typename Codec::Reply> replyValueRoundTrip(typename Codec::Reply value) {
  return replyRoundTrip<Codec>(okReply(std::move(value)));
}

}  // namespace semfuse::wire
