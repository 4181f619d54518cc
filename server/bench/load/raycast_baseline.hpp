#pragma once
// The raycast with nothing else running, through the server and in the library on the same map:
// the server's map is saved through the admin service and loaded here, and both render the same
// poses with the same intrinsics and layers, alternating, so that they see the same machine.
//
// "Nothing else running" is waited for: after a load run the server still finishes what it had
// in hand (the distance field, the live mesh, the objects a query started), and a raycast timed
// then measures that work too. One unmeasured round of every pose comes first (the first
// raycasts of a process fault their scratch in), and the server's cost is the median of the
// per-pose ratios server / library: the poses' raycasts differ by a factor of two, and a ratio of
// two medians could compare a slow pose with a fast one.
#include <sys/types.h>

#include <string>
#include <vector>

#include "bench_support.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::bench::load {

struct RaycastBaseline {
  Timings server_ms;        // MapClient::raycast, request to decoded reply
  Timings library_ms;       // render::raycast on the loaded map, in this process
  Timings ratio;            // per pose and repeat: the server's time over the library's right after it
  double quiet_wait_s = 0;  // how long the server took to fall quiet before the timing
  bool quiet = false;       // it did, within the bound
  std::string error;        // why a part is missing
};

// `server` is the server's process, watched until it uses under 5 % of a core (at most 30 s).
RaycastBaseline measureIdleRaycasts(client::MapClient& map, pid_t server, const std::vector<Pose>& poses,
                                    const PinholeIntrinsics& intrinsics, int repeats);

}  // namespace semfuse::bench::load
