#include "semfuse/dds/error.hpp"

namespace semfuse::dds {

std::string describe(const std::string& what, dds_return_t code) { return what + ": " + dds_strretcode(code); }

DdsError::DdsError(const std::string& what, dds_return_t code)
    : std::runtime_error(describe(what, code)), code_(code) {}

dds_return_t check(dds_return_t rc, const char* what) {
  if (rc < 0) throw DdsError(what, rc);
  return rc;
}

Status toStatus(dds_return_t rc, const char* what) {
  if (rc < 0) return makeError(describe(what, rc));
  return Status::Ok();
}

}  // namespace semfuse::dds
