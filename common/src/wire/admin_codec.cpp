#include <string>

#include "semfuse/wire/ros_codec.hpp"
#include "semfuse/wire/service_codecs.hpp"
#include "semfuse/wire/status_codec.hpp"
#include "service_codec_support.hpp"

namespace semfuse::wire {

static_assert(static_cast<uint8_t>(AdminCommand::kStats) == semfuse_srv_dds__Admin_Request_Constants_STATS);
static_assert(static_cast<uint8_t>(AdminCommand::kSave) == semfuse_srv_dds__Admin_Request_Constants_SAVE);
static_assert(static_cast<uint8_t>(AdminCommand::kLoad) == semfuse_srv_dds__Admin_Request_Constants_LOAD);
static_assert(static_cast<uint8_t>(AdminCommand::kReset) == semfuse_srv_dds__Admin_Request_Constants_RESET);

void AdminCodec::encodeRequest(const Request& request, WireRequest& out) {
  out.command = static_cast<uint8_t>(request.command);
  dds::setString(out.path, request.path);
}

Result<AdminRequest> AdminCodec::decodeRequest(const WireRequest& wire) {
  if (wire.command > static_cast<uint8_t>(AdminCommand::kReset)) {
    return makeError("unknown admin command " + std::to_string(wire.command) + " (0 stats, 1 save, 2 load, 3 reset)");
  }
  return AdminRequest{static_cast<AdminCommand>(wire.command), stringOf(wire.path)};
}

void AdminCodec::encodeReply(const ServiceReply<Reply>& reply, WireReply& out) {
  detail::encodeReplyStatus(reply, out);
  encodeServerStatus(reply.value, stampNow(), out.server_status);
}

Result<ServiceReply<ServerStatus>> AdminCodec::decodeReply(const WireReply& wire) {
  return detail::decodeReplyWith<Reply>(wire, [&] { return decodeServerStatus(wire.server_status); });
}

}  // namespace semfuse::wire
