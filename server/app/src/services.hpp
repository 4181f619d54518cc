#pragma once
// The query services of the wire contract (raycast, labels_at, region, objects, mesh, admin),
// each on its own RpcServer thread. They read the map under the Mapper's shared lock; admin
// load/reset run on the fusion thread, the only writer. Every request gets a reply: a request
// the server cannot serve gets an error status and a message saying why.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "fusion_loop.hpp"
#include "mapper.hpp"
#include "semfuse/dds/participant.hpp"
#include "semfuse/dds/rpc.hpp"
#include "server_config.hpp"
#include "server_state.hpp"
#include "srv.h"
#include "status_message.hpp"

namespace semfuse::server {

class Services {
 public:
  using SnapshotFn = std::function<ServerStatus()>;
  using SaveFn = std::function<Status(const std::string& path)>;

  Services(const dds::Participant& participant, const ServerConfig& config, Mapper& mapper, FusionLoop& fusion,
           ServerState& state, SnapshotFn snapshot, SaveFn save);
  ~Services();

 private:
  void raycast(const semfuse_srv_dds__Raycast_Request_& request, semfuse_srv_dds__Raycast_Response_& reply);
  void labelsAt(const semfuse_srv_dds__LabelsAt_Request_& request, semfuse_srv_dds__LabelsAt_Response_& reply);
  void region(const semfuse_srv_dds__Region_Request_& request, semfuse_srv_dds__Region_Response_& reply);
  void objects(const semfuse_srv_dds__Objects_Request_& request, semfuse_srv_dds__Objects_Response_& reply);
  void mesh(const semfuse_srv_dds__Mesh_Request_& request, semfuse_srv_dds__Mesh_Response_& reply);
  void admin(const semfuse_srv_dds__Admin_Request_& request, semfuse_srv_dds__Admin_Response_& reply);

  // Sets an error status and records it in the log and the status.
  template <class Reply>
  void refuse(Reply& reply, int32_t code, const std::string& service, const std::string& message);

  const ServerConfig& config_;
  Mapper& mapper_;
  FusionLoop& fusion_;
  ServerState& state_;
  SnapshotFn snapshot_;
  SaveFn save_;

  // Meshes being fetched in chunks, newest last; a few are kept so concurrent clients can page.
  std::mutex meshes_mutex_;
  std::map<uint64_t, std::shared_ptr<const std::string>> meshes_;
  uint64_t next_mesh_id_ = 1;

  template <class Req, class Rep>
  using Server = std::unique_ptr<dds::RpcServer<Req, Rep>>;
  Server<semfuse_srv_dds__Raycast_Request_, semfuse_srv_dds__Raycast_Response_> raycast_server_;
  Server<semfuse_srv_dds__LabelsAt_Request_, semfuse_srv_dds__LabelsAt_Response_> labels_at_server_;
  Server<semfuse_srv_dds__Region_Request_, semfuse_srv_dds__Region_Response_> region_server_;
  Server<semfuse_srv_dds__Objects_Request_, semfuse_srv_dds__Objects_Response_> objects_server_;
  Server<semfuse_srv_dds__Mesh_Request_, semfuse_srv_dds__Mesh_Response_> mesh_server_;
  Server<semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_> admin_server_;
};

}  // namespace semfuse::server
