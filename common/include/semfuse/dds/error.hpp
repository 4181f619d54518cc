#pragma once
// How Cyclone's C return codes become C++ errors: constructors throw DdsError (an entity that
// cannot be created leaves nothing useful behind), while hot-path calls (write, take, wait)
// return a Status so that a full queue or a timeout is handled where it happens.
#include <stdexcept>
#include <string>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"

namespace semfuse::dds {

class DdsError : public std::runtime_error {
 public:
  DdsError(const std::string& what, dds_return_t code);
  dds_return_t code() const { return code_; }

 private:
  dds_return_t code_;
};

// "<what>: <dds_strretcode text>", the message used by both error paths.
std::string describe(const std::string& what, dds_return_t code);

// Throws DdsError when rc is negative; returns rc (an entity handle or a count) otherwise.
dds_return_t check(dds_return_t rc, const char* what);

// Status::Ok() for a non-negative rc, else an error carrying the Cyclone text.
Status toStatus(dds_return_t rc, const char* what);

}  // namespace semfuse::dds
