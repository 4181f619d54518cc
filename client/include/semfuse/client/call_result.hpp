#pragma once
// CallResult<T>: the outcome of one request to the server — a value, or a failure that says
// whether the server answered with an error or never answered, because a caller (and the query
// CLI's exit code) treats the two differently. A server's error keeps the kind the server gave it
// (errorCode(), from the reply's status: not found, invalid argument, too large, ...).
#include <string>
#include <utility>

#include "semfuse/core/result.hpp"

namespace semfuse::client {

enum class Failure {
  kNone,
  kTimeout,  // no server matched, or no reply before the deadline
  kServer,   // the server replied with a non-OK status
  kClient,   // the request could not be sent or the reply could not be decoded
};

template <class T>
class [[nodiscard]] CallResult {
 public:
  CallResult(T value) : result_(std::move(value)) {}  // NOLINT(google-explicit-constructor)
  // A failure with the code its kind implies: kUnavailable for a timeout, else kUnspecified.
  CallResult(Failure failure, std::string message)
      : CallResult(failure, Error{std::move(message),
                                  failure == Failure::kTimeout ? ErrorCode::kUnavailable : ErrorCode::kUnspecified}) {}
  CallResult(Failure failure, Error error) : result_(std::move(error)), failure_(failure) {}

  bool ok() const { return result_.ok(); }
  explicit operator bool() const { return ok(); }
  Failure failure() const { return failure_; }
  const T& value() const& { return result_.value(); }
  T& value() & { return result_.value(); }
  T&& value() && { return std::move(result_).value(); }
  const std::string& error() const { return result_.error(); }
  ErrorCode errorCode() const { return result_.errorCode(); }

 private:
  Result<T> result_;
  Failure failure_ = Failure::kNone;
};

// What a call that returns nothing but may fail yields.
struct Done {};

}  // namespace semfuse::client
