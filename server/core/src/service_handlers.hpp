#pragma once
// The query services of the wire contract (idl/semfuse/srv.idl) as plain functions: the decoded
// request and what the service needs in, the reply out, no DDS. The server's DDS adapter
// (services.hpp) decodes each request with its codec (common/wire/service_codecs.hpp), calls
// these, encodes and writes the reply; the fuzzer (fuzz/targets/service_requests.cpp) and the
// tests call them directly. A request they cannot serve gets a reply with an error code and a
// message saying why.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "held_meshes.hpp"
#include "map_access.hpp"
#include "query_limits.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/server_status.hpp"
#include "semfuse/core/service_types.hpp"
#include "semfuse/objects/object_tracker.hpp"

namespace semfuse::server {

// Copies the leaves in view under the map's lock (a few ms), then renders the copy without it.
ServiceReply<RaycastImages> handleRaycast(const RaycastRequest& request, const MapAccess& map,
                                          const QueryLimits& limits);
ServiceReply<std::vector<VoxelSample>> handleLabelsAt(const LabelsAtRequest& request, const MapAccess& map,
                                                      const QueryLimits& limits);
ServiceReply<RegionSummary> handleRegion(const Box& box, const MapAccess& map);
// The map's objects as `tracker` groups and names them (server/objects/README.md): the same
// tracker keeps an object's id across calls and as the map grows. With max_age, the tracker's last
// set when it answered for a map at most that much older than now (the objects refresher keeps it
// so), else grouped from the map as it is. Without a tracker, a fresh one (ids from 1 for this
// call alone: the fuzzer's and the tests' fixed maps).
ServiceReply<std::vector<ObjectInstance>> handleObjects(const ObjectsRequest& request, const MapAccess& map,
                                                        objects::ObjectTracker& tracker);
ServiceReply<std::vector<ObjectInstance>> handleObjects(const ObjectsRequest& request, const MapAccess& map);
// mesh_id 0 extracts a mesh and holds it in `meshes`; later chunks are cut from the held PLY.
// object_id != 0 meshes that object of `tracker`'s (NOT_FOUND when the map has no such object).
ServiceReply<MeshChunk> handleMesh(const MeshRequest& request, const MapAccess& map, HeldMeshes& meshes,
                                   const QueryLimits& limits, objects::ObjectTracker* tracker = nullptr);

// The tracker a server's objects and mesh services share, for a map of this legend and voxel size.
std::unique_ptr<objects::ObjectTracker> makeObjectTracker(const LabelLegend& legend, double voxel_size,
                                                          objects::ObjectParams params = {});

// What the admin service acts on.
struct AdminActions {
  std::string map_file;  // --map: the file of a save or load whose path is ""
  std::function<Status(const std::string& path)> save;
  std::function<Status(const std::string& path)> load;  // replaces the map (the server runs it on the fusion thread)
  std::function<Status()> reset;
  std::function<ServerStatus()> status;  // what every admin reply carries, after the command
  // Records a command that failed, before the reply takes the status (which then shows it).
  std::function<void(const Error& error)> failed;
};
// A command that fails gets the reply code of its error's code (replyCodeOf: a map
// file that is not there NOT_FOUND, an incompatible or damaged one INVALID_ARGUMENT, a busy fusion
// thread UNAVAILABLE); the reply carries the status all the same.
ServiceReply<ServerStatus> handleAdmin(const AdminRequest& request, const AdminActions& actions);

}  // namespace semfuse::server
