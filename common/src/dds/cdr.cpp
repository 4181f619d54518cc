#include "semfuse/dds/cdr.hpp"

#include <cstdio>
#include <cstring>
#include <limits>
#include <string>

#include <dds/ddsi/ddsi_cdrstream.h>
#include <dds/ddsrt/endian.h>

namespace semfuse::dds::detail {
namespace {

// Encapsulation identifiers (DDS-XTypes table 59); semfuse's types are final, so plain CDR
// version 1 is all that is accepted.
constexpr uint8_t kCdrBigEndian = 0x00;
constexpr uint8_t kCdrLittleEndian = 0x01;
constexpr std::size_t kHeaderSize = 4;
constexpr uint32_t kXcdr1 = 1;

}  // namespace

std::vector<uint8_t> serialize(const dds_topic_descriptor_t& descriptor, const void* sample) {
  dds_ostreamLE_t os;
  dds_ostreamLE_init(&os, 0, kXcdr1);
  dds_stream_writeLE(&os, static_cast<const char*>(sample), descriptor.m_ops);
  const std::size_t body = os.x.m_index;
  // The body is padded to a multiple of 4 and the pad count goes in the options word, which
  // is what Cyclone's writer does too.
  const uint8_t padding = static_cast<uint8_t>((4 - body % 4) % 4);
  std::vector<uint8_t> bytes(kHeaderSize + body + padding, 0);
  bytes[1] = kCdrLittleEndian;
  bytes[3] = padding;
  if (body > 0) std::memcpy(bytes.data() + kHeaderSize, os.x.m_buffer, body);
  dds_ostreamLE_fini(&os);
  return bytes;
}

Status deserialize(const dds_topic_descriptor_t& descriptor, const uint8_t* bytes, std::size_t size, void* sample) {
  const std::string type = descriptor.m_typename;
  if (size < kHeaderSize) {
    return makeError(type + ": " + std::to_string(size) + " bytes, shorter than the 4-byte CDR header");
  }
  if (bytes[0] != 0x00 || (bytes[1] != kCdrLittleEndian && bytes[1] != kCdrBigEndian)) {
    char id[8];
    std::snprintf(id, sizeof id, "%02x %02x", bytes[0], bytes[1]);
    return makeError(type + ": unsupported encapsulation " + id + " (expected XCDR1: 00 00 or 00 01)");
  }
  const std::size_t body = size - kHeaderSize;
  if (body > std::numeric_limits<uint32_t>::max()) return makeError(type + ": sample larger than 4 GiB");
  // Every wire type has at least one member, so a header alone is malformed (and an empty body
  // would hand Cyclone a null buffer, which its normalizer declares it never gets).
  if (body == 0) return makeError(type + ": no CDR body after the header");
  // Normalizing validates every length against the buffer and swaps big-endian data in place,
  // so it needs a private, writable copy.
  std::vector<char> data(bytes + kHeaderSize, bytes + size);
  const bool swap = (bytes[1] == kCdrBigEndian) != (DDSRT_ENDIAN == DDSRT_BIG_ENDIAN);
  uint32_t consumed = 0;
  if (!dds_stream_normalize_data(data.data(), &consumed, static_cast<uint32_t>(body), swap, kXcdr1, descriptor.m_ops)) {
    return makeError(type + ": malformed CDR in " + std::to_string(body) +
                     "-byte body (a length or count runs past the end, or a value is invalid)");
  }
  // What follows the body may only be alignment padding. Writers disagree on whether the
  // options word announces it (XTypes 1.3 says so, older ROS 2 stacks leave it 0), so any
  // 0-3 bytes are accepted.
  if (body - consumed > 3) {
    return makeError(type + ": " + std::to_string(body - consumed) + " trailing bytes after the sample");
  }
  dds_istream_t is;
  dds_istream_init(&is, static_cast<uint32_t>(body), data.data(), kXcdr1);
  dds_stream_read(&is, static_cast<char*>(sample), descriptor.m_ops);
  dds_istream_fini(&is);
  return Status::Ok();
}

}  // namespace semfuse::dds::detail
