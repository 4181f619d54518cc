#pragma once
// Result<T>: a value or an error. Used wherever input from outside (the wire, files, datasets)
// can be malformed, so that callers get a precise reason instead of an exception.
//
// An error has a message, for people, and a code, for code: a caller that reacts to the kind of
// failure (a drop reason, a service reply's status, a client's exit code) switches on the code and
// never reads the message. makeError(message) gives the unspecified code, which is right wherever
// nobody needs to tell that failure from others.
#include <cassert>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace semfuse {

enum class ErrorCode : uint8_t {
  kUnspecified = 0,  // nothing more specific: the message says what went wrong
  kInvalidArgument,  // the input is malformed, out of range or incompatible with what it meets
  kNotFound,         // what was named does not exist (a file, a held mesh)
  kTooLarge,         // the input exceeds a configured limit
  kUnavailable,      // not now: busy, shutting down, or no answer in time
  kInternal,         // a fault on the side that answers (I/O, a broken invariant)
};

// "unspecified", "invalid_argument", ... for logs and messages.
inline const char* errorCodeName(ErrorCode code) {
  switch (code) {
    case ErrorCode::kUnspecified:
      return "unspecified";
    case ErrorCode::kInvalidArgument:
      return "invalid_argument";
    case ErrorCode::kNotFound:
      return "not_found";
    case ErrorCode::kTooLarge:
      return "too_large";
    case ErrorCode::kUnavailable:
      return "unavailable";
    case ErrorCode::kInternal:
      return "internal";
  }
  return "unknown";
}

struct Error {
  std::string message;
  ErrorCode code = ErrorCode::kUnspecified;

  // The same error with context in front of its message ("loading map x: " + message).
  Error prefixed(const std::string& context) const { return {context + message, code}; }
};

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : state_(std::move(value)) {}      // NOLINT(google-explicit-constructor)
  Result(Error error) : state_(std::move(error)) {}  // NOLINT(google-explicit-constructor)

  bool ok() const { return std::holds_alternative<T>(state_); }
  explicit operator bool() const { return ok(); }

  const T& value() const& {
    assert(ok());
    return std::get<T>(state_);
  }
  T& value() & {
    assert(ok());
    return std::get<T>(state_);
  }
  T&& value() && {
    assert(ok());
    return std::get<T>(std::move(state_));
  }
  const std::string& error() const { return errorInfo().message; }
  ErrorCode errorCode() const { return errorInfo().code; }
  // Message and code together, to pass the error on: `if (!r) return r.errorInfo();`.
  const Error& errorInfo() const {
    assert(!ok());
    return std::get<Error>(state_);
  }

 private:
  std::variant<T, Error> state_;
};

// Result of an operation that yields nothing but may fail.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), failed_(true) {}  // NOLINT(google-explicit-constructor)
  static Status Ok() { return {}; }

  bool ok() const { return !failed_; }
  explicit operator bool() const { return ok(); }
  const std::string& error() const { return error_.message; }  // empty when ok
  ErrorCode errorCode() const { return error_.code; }          // kUnspecified when ok
  const Error& errorInfo() const { return error_; }

 private:
  Error error_;
  bool failed_ = false;
};

inline Error makeError(std::string message) { return Error{std::move(message)}; }
inline Error makeError(ErrorCode code, std::string message) { return Error{std::move(message), code}; }
// The most common coded error: input that is malformed or out of range.
inline Error invalidArgument(std::string message) { return makeError(ErrorCode::kInvalidArgument, std::move(message)); }

}  // namespace semfuse
