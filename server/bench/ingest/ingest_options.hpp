#pragma once
// The command line of `semfuse-bench ingest` (bench_ingest.cpp declares the flags).
#include <cstddef>
#include <string>
#include <vector>

#include "bench_support.hpp"

namespace semfuse::bench::ingest {

struct IngestOptions {
  std::string server =
#ifdef SEMFUSE_SERVER_EXE
      SEMFUSE_SERVER_EXE;
#else
      "";
#endif
  std::string data = redkitchenDir().string();
  std::size_t frames = 500;
  double duration_s = 10.0;
  double rate_hz = 30.0;
  std::vector<int> cameras{1, 2, 4};
  std::string depth = "raw";
  double raycast_duration_s = 10.0;  // 0 = no raycast phase
  int raycast_period_ms = 100;       // a viewer refreshing at 10 Hz
  int domain = -1;                   // -1 = derived from the pid
  bool follow_map = false;           // a MapFollower follows the live mesh during the runs
  std::vector<std::string> server_args;
};

}  // namespace semfuse::bench::ingest
