#include "semfuse/wire/reply_status.hpp"

#include "srv.h"

namespace semfuse::wire {

int32_t replyStatusOf(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kNoPose:
      return semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT;
    case ErrorCode::kNotFound:
      return semfuse_srv_dds__Status_Constants_NOT_FOUND;
    case ErrorCode::kTooLarge:
      return semfuse_srv_dds__Status_Constants_TOO_LARGE;
    case ErrorCode::kUnavailable:
      return semfuse_srv_dds__Status_Constants_UNAVAILABLE;
    case ErrorCode::kUnspecified:
    case ErrorCode::kInternal:
      break;
  }
  return semfuse_srv_dds__Status_Constants_INTERNAL;
}

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
