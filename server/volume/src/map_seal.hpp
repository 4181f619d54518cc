#pragma once
// Internal: the integrity seal of a map file. A map file is OpenVDB's stream bytes (the
// "payload") followed by a 32-byte trailer, all integers little-endian:
//   offset  0  8 bytes  magic "SFMAPEND"
//           8  u32      seal version (kSealVersion)
//          12  u32      0 (reserved)
//          16  u64      payload length in bytes
//          24  u64      CRC-64/XZ of the payload
// Loading checks the whole file against its trailer before OpenVDB parses a single byte:
// OpenVDB's reader trusts the sizes in a file (a corrupt one can make it allocate gigabytes or
// crash), so a truncated, extended or corrupted file has to be refused before it gets there.
// OpenVDB's own readers (io::File, other tools) stop after the last grid and ignore the trailer.
// The CRC detects accidents (torn writes, bit rot, truncation), not forgery: anyone who can write
// the map file can also write a matching trailer.
#include <cstddef>
#include <cstdint>
#include <streambuf>
#include <string>
#include <string_view>

#include "semfuse/core/result.hpp"

namespace semfuse::volume::detail {

inline constexpr uint32_t kSealVersion = 1;
inline constexpr std::size_t kSealTrailerSize = 32;

// CRC-64/XZ (ECMA-182 polynomial, reflected, initial value and final xor all ones), fed in pieces.
class Crc64 {
 public:
  void update(const char* data, std::size_t size);
  uint64_t value() const { return ~state_; }

 private:
  uint64_t state_ = ~uint64_t{0};
};

// An output stream buffer that forwards every byte to `target` and keeps the CRC and the count
// of what went through, so a file is sealed while it is written (no second pass, no copy).
class CrcForwardingBuffer : public std::streambuf {
 public:
  explicit CrcForwardingBuffer(std::streambuf& target) : target_(target) {}
  uint64_t crc() const { return crc_.value(); }
  uint64_t bytes() const { return bytes_; }

 protected:
  int_type overflow(int_type ch) override;
  std::streamsize xsputn(const char* data, std::streamsize size) override;
  int sync() override { return target_.pubsync(); }

 private:
  std::streambuf& target_;
  Crc64 crc_;
  uint64_t bytes_ = 0;
};

// The trailer for a payload of `bytes` bytes with CRC `crc`.
std::string sealTrailer(uint64_t bytes, uint64_t crc);

// The payload of a whole map file (a view into `file`) once its trailer matches its length and
// CRC; otherwise an error that says what is wrong (no trailer, other seal version, length, CRC).
Result<std::string_view> verifySeal(std::string_view file);

// A read-only input stream buffer over bytes already in memory (seekable), for OpenVDB's reader.
class MemoryReadBuffer : public std::streambuf {
 public:
  explicit MemoryReadBuffer(std::string_view bytes);

 protected:
  pos_type seekoff(off_type offset, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
  pos_type seekpos(pos_type position, std::ios_base::openmode which) override;
};

}  // namespace semfuse::volume::detail
