#pragma once
// Writer<T>: publishes samples of wire type T on a topic.
#include <string>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/dds/entity.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/match.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topic.hpp"

namespace semfuse::dds {

template <class T>
class Writer {
 public:
  Writer(const Topic<T>& topic, const Qos& qos)
      : topic_name_(topic.name()),
        entity_(check(dds_create_writer(topic.participant(), topic.handle(), qos.get(), nullptr),
                      ("create writer on " + topic.name()).c_str())) {}

  dds_entity_t handle() const { return entity_.handle(); }
  const std::string& topicName() const { return topic_name_; }

  // Fails with a timeout when reliable readers do not acknowledge within max_blocking_time.
  Status write(const T& sample) const { return toStatus(dds_write(entity_.handle(), &sample), "write"); }

  // Waits until every matched reliable reader has acknowledged every sample written so far: a
  // writer that stops, or whose last samples matter, calls it before it goes.
  Status waitForAcknowledgements(dds_duration_t timeout) const {
    return toStatus(dds_wait_for_acks(entity_.handle(), timeout),
                    ("wait for acknowledgements on " + topic_name_).c_str());
  }

  int32_t matchedReaders() const { return dds::matchedReaders(entity_.handle()); }
  bool waitForReaders(int32_t count, dds_duration_t timeout) const {
    return dds::waitForReaders(entity_.handle(), count, timeout);
  }

 private:
  std::string topic_name_;
  Entity entity_;
};

}  // namespace semfuse::dds
