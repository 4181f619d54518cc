#pragma once
// What every DDS test needs: a loopback-only Cyclone configuration that lets two processes on
// this host find each other without multicast, and a domain id + topic prefix of its own so
// tests running in parallel never see each other's traffic.
#include <cstdlib>
#include <string>

#include <unistd.h>

#include <dds/dds.h>
#include <gtest/gtest.h>

#include "test_domain.hpp"

namespace semfuse::dds::testing {

// Unicast discovery on "lo": ParticipantIndex auto gives each participant a well-known port,
// which the localhost peer entry probes.
inline constexpr const char* kLoopbackConfig =
    "<CycloneDDS><Domain><General><Interfaces><NetworkInterface name=\"lo\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast></General>"
    "<Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>50"
    "</MaxAutoParticipantIndex><Peers><Peer address=\"localhost\"/></Peers></Discovery>"
    "<Tracing><Verbosity>warning</Verbosity></Tracing></Domain></CycloneDDS>";

// Call before the first participant; child processes inherit it.
inline void useLoopbackConfig() { ::setenv("CYCLONEDDS_URI", kLoopbackConfig, 1); }

// One domain per test process (ctest runs each test in its own process), held by no other test.
inline dds_domainid_t testDomain() { return static_cast<dds_domainid_t>(semfuse::testing::reserveTestDomain()); }

// "<base>_<pid>_<test name>_<n>": unique even if two processes land on the same domain, and
// across --gtest_repeat runs, whose endpoints of the previous round may still be known.
inline std::string uniqueName(const std::string& base) {
  static int counter = 0;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return base + "_" + std::to_string(::getpid()) + "_" + (info ? info->name() : "x") + "_" + std::to_string(counter++);
}

inline constexpr dds_duration_t kDiscoveryTimeout = DDS_SECS(15);

}  // namespace semfuse::dds::testing
