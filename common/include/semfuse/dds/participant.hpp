#pragma once
// A domain participant. Cyclone reads its configuration from CYCLONEDDS_URI when the first
// participant of a domain is created, so set that variable before constructing one.
#include <dds/dds.h>

#include "semfuse/dds/entity.hpp"

namespace semfuse::dds {

class Participant {
 public:
  explicit Participant(dds_domainid_t domain = DDS_DOMAIN_DEFAULT);

  dds_entity_t handle() const { return entity_.handle(); }
  dds_domainid_t domain() const;

 private:
  Entity entity_;
};

}  // namespace semfuse::dds
