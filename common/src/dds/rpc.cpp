#include "semfuse/dds/rpc.hpp"

#include <random>

namespace semfuse::dds {

uint64_t newClientGuid() {
  // random_device is the OS entropy source on Linux; a 64-bit draw makes collisions between
  // the handful of clients of one service practically impossible.
  static std::mutex mutex;
  static std::random_device device;
  std::lock_guard<std::mutex> lock(mutex);
  uint64_t guid = 0;
  while (guid == 0) guid = (static_cast<uint64_t>(device()) << 32) | device();
  return guid;
}

}  // namespace semfuse::dds
