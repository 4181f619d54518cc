#pragma once
// CDR serialization of wire types, byte for byte as Cyclone puts them on the wire: the 4-byte
// encapsulation header (00 01 = XCDR1 little endian, then the options word whose low two bits
// count the padding bytes at the end, as DDS-XTypes 7.6.3.1.2 defines) followed by the
// plain-CDR body, aligned relative to the first byte after the header.
#include <cstddef>
#include <cstdint>
#include <vector>

#include <dds/dds.h>

#include "semfuse/core/result.hpp"
#include "semfuse/dds/sample.hpp"

namespace semfuse::dds {

namespace detail {
std::vector<uint8_t> serialize(const dds_topic_descriptor_t& descriptor, const void* sample);
Status deserialize(const dds_topic_descriptor_t& descriptor, const uint8_t* bytes, std::size_t size, void* sample);
}  // namespace detail

template <class T>
std::vector<uint8_t> serialize(const T& sample) {
  return detail::serialize(descriptorOf<T>(), &sample);
}

// Validates the bytes against T's definition (header, lengths, bounds) before decoding; any
// malformed input is an error naming the problem, never a read past the buffer.
template <class T>
Result<Sample<T>> deserialize(const uint8_t* bytes, std::size_t size) {
  Sample<T> sample;
  if (Status s = detail::deserialize(descriptorOf<T>(), bytes, size, sample.get()); !s) {
    return s.errorInfo();
  }
  return sample;
}

template <class T>
Result<Sample<T>> deserialize(const std::vector<uint8_t>& bytes) {
  return deserialize<T>(bytes.data(), bytes.size());
}

}  // namespace semfuse::dds
