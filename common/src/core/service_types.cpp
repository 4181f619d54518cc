#include "semfuse/core/service_types.hpp"

namespace semfuse {

ReplyCode replyCodeOf(ErrorCode code) {
  switch (code) {
    case ErrorCode::kInvalidArgument:
      return ReplyCode::kInvalidArgument;
    case ErrorCode::kNotFound:
      return ReplyCode::kNotFound;
    case ErrorCode::kTooLarge:
      return ReplyCode::kTooLarge;
    case ErrorCode::kUnavailable:
      return ReplyCode::kUnavailable;
    case ErrorCode::kUnspecified:
    case ErrorCode::kInternal:
      break;
  }
  return ReplyCode::kInternal;
}

}  // namespace semfuse
