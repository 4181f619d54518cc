#pragma once
// Topic<T>: a named topic of wire type T in a participant.
#include <string>

#include <dds/dds.h>

#include "semfuse/dds/entity.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/type_support.hpp"

namespace semfuse::dds {

template <class T>
class Topic {
 public:
  Topic(const Participant& participant, std::string name, const Qos& qos = Qos())
      : participant_(participant.handle()), name_(std::move(name)) {
    const std::string what = "create topic " + name_;
    entity_ = Entity(
        check(dds_create_topic(participant_, &descriptorOf<T>(), name_.c_str(), qos.get(), nullptr), what.c_str()));
  }

  dds_entity_t handle() const { return entity_.handle(); }
  dds_entity_t participant() const { return participant_; }
  const std::string& name() const { return name_; }

 private:
  dds_entity_t participant_;
  std::string name_;
  Entity entity_;
};

}  // namespace semfuse::dds
