#pragma once
// The raycast with nothing else running, through the server and in the library on the same map:
// the server's map is saved through the admin service and loaded here, and both render the same
// poses with the same intrinsics and layers, alternating, so that they see the same machine.
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "semfuse/client/map_client.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse::bench::load {

struct RaycastBaseline {
  Timings server_ms;   // MapClient::raycast, request to decoded reply
  Timings library_ms;  // render::raycast on the loaded map, in this process
  std::string error;   // why a part is missing
};

RaycastBaseline measureIdleRaycasts(client::MapClient& map, const std::vector<Pose>& poses,
                                    const PinholeIntrinsics& intrinsics, int repeats);

}  // namespace semfuse::bench::load
