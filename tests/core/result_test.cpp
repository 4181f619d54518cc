// Errors carry a code beside their message: makeError(message) is unspecified, a code given is
// kept through Result, Status and prefixing, and every code has its own name.
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "semfuse/core/result.hpp"

using namespace semfuse;

namespace {
Result<int> parsePositive(int value) {
  if (value <= 0) return makeError(ErrorCode::kInvalidArgument, "value " + std::to_string(value) + " is not positive");
  return value;
}
Status check(int value) {
  auto parsed = parsePositive(value);
  if (!parsed) return parsed.errorInfo().prefixed("check: ");
  return Status::Ok();
}
}  // namespace

TEST(ErrorCodes, MakeErrorWithoutACodeIsUnspecified) {
  const Error error = makeError("something failed");
  EXPECT_EQ(error.code, ErrorCode::kUnspecified);
  Status status = error;
  EXPECT_EQ(status.errorCode(), ErrorCode::kUnspecified);
  EXPECT_EQ(status.error(), "something failed");
}

TEST(ErrorCodes, ResultAndStatusKeepTheCodeThroughPrefixing) {
  auto bad = parsePositive(-2);
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.errorCode(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(bad.error(), "value -2 is not positive");

  Status passed_on = check(-2);
  EXPECT_FALSE(passed_on.ok());
  EXPECT_EQ(passed_on.errorCode(), ErrorCode::kInvalidArgument);
  EXPECT_EQ(passed_on.error(), "check: value -2 is not positive");
  EXPECT_EQ(passed_on.errorInfo().message, passed_on.error());

  Status fine = check(3);
  EXPECT_TRUE(fine.ok());
  EXPECT_EQ(fine.errorCode(), ErrorCode::kUnspecified);
  EXPECT_EQ(fine.error(), "");
}

TEST(ErrorCodes, EveryCodeHasItsOwnName) {
  const ErrorCode codes[] = {ErrorCode::kUnspecified, ErrorCode::kInvalidArgument, ErrorCode::kNotFound,
                             ErrorCode::kTooLarge,    ErrorCode::kUnavailable,     ErrorCode::kInternal};
  std::set<std::string> names;
  for (ErrorCode code : codes) names.insert(errorCodeName(code));
  EXPECT_EQ(names.size(), std::size(codes));
  EXPECT_EQ(names.count("unknown"), 0u);
  EXPECT_STREQ(errorCodeName(ErrorCode::kInvalidArgument), "invalid_argument");
}
