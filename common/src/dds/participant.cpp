#include "semfuse/dds/participant.hpp"

#include <string>

#include "semfuse/dds/error.hpp"

namespace semfuse::dds {

Participant::Participant(dds_domainid_t domain)
    : entity_(check(dds_create_participant(domain, nullptr, nullptr),
                    ("create participant in domain " + std::to_string(domain) + " (check CYCLONEDDS_URI)").c_str())) {}

dds_domainid_t Participant::domain() const {
  dds_domainid_t id = 0;
  check(dds_get_domainid(entity_.handle(), &id), "get domain id");
  return id;
}

}  // namespace semfuse::dds
