// Service reply statuses and error codes map both ways: what the server replies for a code, the
// client reads back as that code; codes without a status of their own go to the nearest one.
#include <gtest/gtest.h>

#include "semfuse/wire/reply_status.hpp"
#include "srv.h"

using namespace semfuse;
using semfuse::wire::errorCodeOfReplyStatus;
using semfuse::wire::replyStatusOf;

TEST(ReplyStatus, CodesWithAStatusRoundTrip) {
  for (ErrorCode code : {ErrorCode::kInvalidArgument, ErrorCode::kNotFound, ErrorCode::kTooLarge,
                         ErrorCode::kUnavailable, ErrorCode::kInternal}) {
    EXPECT_EQ(errorCodeOfReplyStatus(replyStatusOf(code)), code) << errorCodeName(code);
  }
  EXPECT_EQ(replyStatusOf(ErrorCode::kInvalidArgument), semfuse_srv_dds__Status_Constants_INVALID_ARGUMENT);
  EXPECT_EQ(replyStatusOf(ErrorCode::kNotFound), semfuse_srv_dds__Status_Constants_NOT_FOUND);
  EXPECT_EQ(replyStatusOf(ErrorCode::kTooLarge), semfuse_srv_dds__Status_Constants_TOO_LARGE);
  EXPECT_EQ(replyStatusOf(ErrorCode::kUnavailable), semfuse_srv_dds__Status_Constants_UNAVAILABLE);
}

TEST(ReplyStatus, CodesWithoutAStatusGoToTheNearestAndNeverToOk) {
  EXPECT_EQ(replyStatusOf(ErrorCode::kUnspecified), semfuse_srv_dds__Status_Constants_INTERNAL);
  for (int code = 0; code <= static_cast<int>(ErrorCode::kInternal); ++code)
    EXPECT_NE(replyStatusOf(static_cast<ErrorCode>(code)), semfuse_srv_dds__Status_Constants_OK) << code;
}

TEST(ReplyStatus, AStatusThisBuildDoesNotKnowIsUnspecified) {
  EXPECT_EQ(errorCodeOfReplyStatus(99), ErrorCode::kUnspecified);
  EXPECT_EQ(errorCodeOfReplyStatus(-1), ErrorCode::kUnspecified);
}
