#include "semfuse/wire/reply_status.hpp"

#include "semfuse/core/service_types.hpp"
#include "srv.h"

namespace semfuse::wire {

// ReplyCode's values are the statuses' (asserted in service_codec_support.hpp).
int32_t replyStatusOf(ErrorCode code) { return static_cast<int32_t>(replyCodeOf(code)); }

ErrorCode errorCodeOfReplyStatus(int32_t status) {
  switch (status) {
    case semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT:
      return ErrorCode::kInvalidArgument;
    case semfuse_srv_dds__Status_Constants_NOT_FOUND:
      return ErrorCode::kNotFound;
    case semfuse_srv_dds__Status_Constants_TOO_LARGE:
      return ErrorCode::kTooLarge;
    case semfuse_srv_dds__Status_Constants_UNAVAILABLE:
      return ErrorCode::kUnavailable;
    case semfuse_srv_dds__Status_Constants_INTERNAL:
      return ErrorCode::kInternal;
    default:
      return ErrorCode::kUnspecified;
  }
}

}  // namespace semfuse::wire
