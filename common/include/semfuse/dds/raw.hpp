#pragma once
// Serialized-data access to topics: a writer that publishes CDR bytes as they are (to inject
// bytes produced elsewhere: ROS 2 nodes, fuzzers, recordings) and a take that returns the bytes
// exactly as they arrived.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/dds/entity.hpp"
#include "semfuse/dds/error.hpp"
#include "semfuse/dds/match.hpp"
#include "semfuse/dds/qos.hpp"
#include "semfuse/dds/topic.hpp"

struct ddsi_sertype;

namespace semfuse::dds {

namespace detail {
// Cyclone 0.10's C API has no getter for a topic's serialization type; this finds it by writing
// a sample through a private writer/reader pair on the topic, then keeps a reference to it.
ddsi_sertype* acquireSertype(dds_entity_t topic, const dds_topic_descriptor_t& descriptor);
void releaseSertype(ddsi_sertype* sertype);
Status writeSerialized(dds_entity_t writer, ddsi_sertype* sertype, const uint8_t* bytes, std::size_t size);
Result<std::vector<std::vector<uint8_t>>> takeSerialized(dds_entity_t reader, std::size_t max);
}  // namespace detail

template <class T>
class RawWriter {
 public:
  RawWriter(const Topic<T>& topic, const Qos& qos)
      : sertype_(detail::acquireSertype(topic.handle(), descriptorOf<T>())),
        entity_(check(dds_create_writer(topic.participant(), topic.handle(), qos.get(), nullptr),
                      ("create raw writer on " + topic.name()).c_str())) {}
  ~RawWriter() { detail::releaseSertype(sertype_); }
  RawWriter(RawWriter&& other) noexcept
      : sertype_(std::exchange(other.sertype_, nullptr)), entity_(std::move(other.entity_)) {}
  RawWriter& operator=(RawWriter&&) = delete;
  RawWriter(const RawWriter&) = delete;
  RawWriter& operator=(const RawWriter&) = delete;

  dds_entity_t handle() const { return entity_.handle(); }

  // bytes: header + CDR body. Malformed bytes are rejected before anything is sent.
  Status write(const uint8_t* bytes, std::size_t size) const {
    return detail::writeSerialized(entity_.handle(), sertype_, bytes, size);
  }
  Status write(const std::vector<uint8_t>& bytes) const { return write(bytes.data(), bytes.size()); }

  bool waitForReaders(int32_t count, dds_duration_t timeout) const {
    return dds::waitForReaders(entity_.handle(), count, timeout);
  }

 private:
  ddsi_sertype* sertype_;
  Entity entity_;
};

// Takes up to max samples from any reader, as serialized bytes (header included).
inline Result<std::vector<std::vector<uint8_t>>> takeSerialized(dds_entity_t reader, std::size_t max = 32) {
  return detail::takeSerialized(reader, max);
}

}  // namespace semfuse::dds
