#pragma once
// The map server's services (raycast, labels_at, region, objects, mesh, admin) as plain C++
// values: what a client asks and what the server answers. The server's handlers and the client
// library work with these; common/wire's service codecs turn them into the generated wire
// structs of idl/semfuse/srv.idl and back.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/raycast_layers.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/server_status.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// The status every reply carries (Status_Constants in srv.idl, same values).
enum class ReplyCode : int32_t {
  kOk = 0,
  kInvalidArgument = 1,  // the request is malformed or asks for something impossible
  kNotFound = 2,         // what it names is gone (a mesh no longer held)
  kUnavailable = 3,      // not now: the server is busy or shutting down
  kInternal = 4,         // the server failed
  kTooLarge = 5,         // beyond the server's limits
};

// The non-OK reply code for an error of `code`. A code with no reply code of its own goes to the
// nearest one: kUnspecified to kInternal (an unclassified failure of the server). Both the server's handlers and the
// wire (wire/reply_status.hpp) use this one mapping.
ReplyCode replyCodeOf(ErrorCode code);

// A service's answer: a code, a message (why, when it failed; what was done, for admin) and the
// value. A failed reply leaves the value as it is by default, except where a service says
// otherwise (admin answers with the server status whatever happened).
template <class T>
struct ServiceReply {
  ReplyCode code = ReplyCode::kOk;
  std::string message;
  T value{};

  bool ok() const { return code == ReplyCode::kOk; }
  static ServiceReply failure(ReplyCode code, std::string message) {
    ServiceReply reply;
    reply.code = code;
    reply.message = std::move(message);
    return reply;
  }
};

// An axis-aligned box in the world frame, metres.
struct Box {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
};

// raycast: render the map from a camera.
struct RaycastRequest {
  Pose camera_to_world = Pose::Identity();
  PinholeIntrinsics intrinsics;
  RaycastLayers layers = kAllLayers;
  float max_range = 0.0F;  // metres; 0 (or not finite): the server's default
};
// A rendered view of the map. Layers that were not requested are empty.
struct RaycastImages {
  cv::Mat depth;       // CV_32FC1 metres along the camera z axis, 0 = no surface
  cv::Mat normals;     // CV_32FC3 world-frame unit normals
  cv::Mat labels;      // CV_16UC1, 0 = unlabeled
  cv::Mat confidence;  // CV_32FC1
  cv::Mat color;       // CV_8UC3 RGB
};

// labels_at: probe voxels at points (world frame, metres).
struct LabelsAtRequest {
  std::vector<Eigen::Vector3d> points;
};
struct VoxelSample {
  bool observed = false;
  LabelId label = kUnlabeled;
  float confidence = 0.0F;
  float tsdf = 0.0F;
  float weight = 0.0F;
};

// region (request: a Box): what is in a box.
struct LabelArea {
  LabelId label = kUnlabeled;
  uint64_t surface_voxels = 0;
  double area_m2 = 0.0;
};
struct RegionSummary {
  std::vector<LabelArea> histogram;
  uint64_t observed_voxels = 0;
  uint64_t occupied_voxels = 0;
  uint64_t free_voxels = 0;
  double occupancy = 0.0;
};

// objects: the object instances of the map (server/objects/README.md): whole objects with ids that
// stay with them while the map grows.
struct ObjectsRequest {
  LabelId label = kUnlabeled;           // kUnlabeled = objects of every label
  uint32_t min_voxels = 0;              // leave out objects of fewer surface voxels
  std::optional<Eigen::Vector3d> near;  // only objects whose surface comes within radius of this point
  double radius = 0.0;                  // metres, with near
  bool include_fragments = false;       // also the pieces too small to be objects
  // Seconds: the objects the server keeps up to date in the background will do when they were
  // grouped from a map at most this much older than the request (an answer at once while the map
  // grows); 0 = grouped from the map as it is.
  double max_age_s = 0.0;
};
// A frame of a camera, as the frames topic names it.
struct FrameRef {
  std::string camera_id;
  uint64_t seq = 0;
};
struct ObjectInstance {
  uint32_t id = 0;
  LabelId label = kUnlabeled;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero();  // axis-aligned
  Eigen::Vector3d bbox_max = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  uint64_t voxel_count = 0;  // surface voxels
  float mean_confidence = 0.0F;
  double area_m2 = 0.0;  // of its surface
  // The oriented box: upright around the up axis when the server knows it, else principal axes.
  Eigen::Vector3d box_center = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_half_extents = Eigen::Vector3d::Zero();
  Eigen::Quaterniond box_rotation = Eigen::Quaterniond::Identity();  // box axes to world
  bool fragment = false;
  // Frames that saw it, most of its surface first (at most 16), and how many did, as far as its
  // leaves remember (each the latest 16 frames that saw it).
  std::vector<FrameRef> frames;
  uint32_t frame_count = 0;
};

// mesh: a PLY of the map, fetched in chunks. The first request has mesh_id 0 and chunk_index 0;
// its reply names the mesh and the chunk count; later requests ask for (mesh_id, chunk_index).
struct MeshRequest {
  std::optional<Box> box;  // only the part of the map inside it
  uint64_t mesh_id = 0;
  uint32_t chunk_index = 0;
  uint32_t object_id = 0;  // only this object's surface (objects); 0 = the map
};
struct MeshChunk {
  uint64_t mesh_id = 0;
  uint32_t chunk_index = 0;
  uint32_t chunk_count = 0;
  uint64_t total_bytes = 0;  // of the whole PLY
  uint32_t vertex_count = 0;
  uint32_t face_count = 0;
  std::vector<uint8_t> ply;  // this chunk's bytes
};

// admin: control the server; every reply carries its status (ServerStatus).
enum class AdminCommand : uint8_t { kStats = 0, kSave = 1, kLoad = 2, kReset = 3 };
struct AdminRequest {
  AdminCommand command = AdminCommand::kStats;
  std::string path;  // save / load: the file ("" = the server's --map file)
};

}  // namespace semfuse
