#pragma once
// A DDS domain id that no other semfuse test on this host holds. ctest runs tests in parallel and
// each starts servers and clients on loopback: two tests on one domain would see each other's
// frames and replies. A test process takes the first free id from a start that depends on its pid
// by holding an flock on /tmp/semfuse-domains/<id>.lock until it exits; the C++, Python
// (tests/python/conftest.py) and shell (tests/deploy/lib.sh) tests all reserve this way.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <stdexcept>
#include <string>

namespace semfuse::testing {

// A free domain, held until the process exits; every call takes another one.
inline int reserveAnotherTestDomain() {
  const std::string folder = "/tmp/semfuse-domains";
  ::mkdir(folder.c_str(), 0777);
  ::chmod(folder.c_str(), 01777);          // several users on one host share it; best effort
  constexpr int kFirst = 1, kCount = 230;  // Cyclone takes ids 0..232; 0 is everyone's default
  const int start = static_cast<int>(::getpid() % kCount);
  for (int k = 0; k < kCount; ++k) {
    const int id = kFirst + (start + k) % kCount;
    const std::string lock = folder + "/" + std::to_string(id) + ".lock";
    // O_CLOEXEC: the servers a test starts must not keep its domain after the test ends.
    const int fd = ::open(lock.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return id;  // held until the process exits
    ::close(fd);
  }
  throw std::runtime_error("no free DDS test domain under " + folder);
}

// The process's domain, reserved on first use.
inline int reserveTestDomain() {
  static const int domain = reserveAnotherTestDomain();
  return domain;
}

}  // namespace semfuse::testing
