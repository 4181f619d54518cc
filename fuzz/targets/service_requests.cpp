// Fuzz target: the query services' requests. First byte picks the service (0 raycast,
// 1 labels_at, 2 region, 3 objects, 4 mesh), the rest is its request's CDR as the RpcServer
// receives it. The request then meets the same checks and the same map functions as in
// server/app/src/services.cpp, on a small labeled map: render::prepareRaycast + raycast, sampleAt,
// summarizeRegion, findObjects, render::extractMesh. (The DDS reply plumbing is left out.)
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fuzz_support.hpp"
#include "map_queries.hpp"
#include "semfuse/core/camera_check.hpp"
#include "semfuse/core/legend.hpp"
#include "semfuse/dds/cdr.hpp"
#include "semfuse/render/mesh.hpp"
#include "semfuse/render/raycast.hpp"
#include "semfuse/wire/frame_codec.hpp"
#include "semfuse/wire/validation.hpp"
#include "srv.h"
#include "tiny_map.hpp"

namespace {
using namespace semfuse;

// services.cpp serves up to --max-raycast-pixels (default 2048^2); a smaller bound keeps every
// input fast without changing which code runs.
constexpr uint64_t kMaxRaycastPixels = 64 * 64;
constexpr uint32_t kMaxPointsPerQuery = 1u << 20;

const volume::LabeledVolume& tinyMap() {
  static const volume::LabeledVolume map = fuzz::makeTinyMap();
  return map;
}
const LabelLegend& legend() {
  static const LabelLegend voc = *builtinLegend("voc");
  return voc;
}

Eigen::Vector3d toEigen(const geometry_msgs_msg_dds__Point_& p) { return {p.x, p.y, p.z}; }
bool validBox(const Eigen::Vector3d& min, const Eigen::Vector3d& max) {
  return min.allFinite() && max.allFinite() && !(max.array() < min.array()).any();
}

template <class Request>
const Request* decoded(dds::Sample<Request>& holder, const uint8_t* data, size_t size) {
  auto sample = dds::deserialize<Request>(data, size);
  if (!sample) return nullptr;
  holder = std::move(sample).value();
  return holder.get();
}

void raycast(const semfuse_srv_dds__Raycast_Request_& request) {
  const uint64_t pixels = uint64_t{request.intrinsics.width} * request.intrinsics.height;
  if (pixels > kMaxRaycastPixels) return;
  const PinholeIntrinsics intrinsics{static_cast<int>(request.intrinsics.width),
                                     static_cast<int>(request.intrinsics.height),
                                     request.intrinsics.fx,
                                     request.intrinsics.fy,
                                     request.intrinsics.cx,
                                     request.intrinsics.cy};
  if (!checkIntrinsics(intrinsics, wire::kMaxImageSide)) return;
  const Pose pose = wire::poseFromRowMajor(request.camera_to_world);
  if (!checkRigidPose(pose)) return;
  if (request.layers == 0 || request.layers > kAllLayers) return;
  render::RaycastOptions options;
  options.layers = request.layers;
  if (std::isfinite(request.max_range) && request.max_range > 0.0f) options.max_depth = request.max_range;
  // As the server does: copy the leaves in view, then render the copy.
  auto prepared = render::prepareRaycast(tinyMap(), intrinsics, pose, options);
  if (!prepared) return;
  auto images = render::raycast(std::move(prepared.value()));
  SEMFUSE_FUZZ_CHECK(images.ok());
  if (request.layers & kDepthLayer) {
    SEMFUSE_FUZZ_CHECK(images.value().depth.cols == intrinsics.width && images.value().depth.rows == intrinsics.height);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int service = data[0] % 5;
  ++data;
  --size;
  switch (service) {
    case 0: {
      dds::Sample<semfuse_srv_dds__Raycast_Request_> holder;
      if (const auto* request = decoded(holder, data, size)) raycast(*request);
      break;
    }
    case 1: {
      dds::Sample<semfuse_srv_dds__LabelsAt_Request_> holder;
      const auto* request = decoded(holder, data, size);
      if (!request || request->points._length > kMaxPointsPerQuery) break;
      std::vector<Eigen::Vector3d> points;
      for (uint32_t i = 0; i < request->points._length; ++i) points.push_back(toEigen(request->points._buffer[i]));
      SEMFUSE_FUZZ_CHECK(server::sampleAt(tinyMap(), points).size() == points.size());
      break;
    }
    case 2: {
      dds::Sample<semfuse_srv_dds__Region_Request_> holder;
      const auto* request = decoded(holder, data, size);
      if (!request || !validBox(toEigen(request->min), toEigen(request->max))) break;
      const auto summary = server::summarizeRegion(tinyMap(), toEigen(request->min), toEigen(request->max));
      SEMFUSE_FUZZ_CHECK(summary.occupied_voxels + summary.free_voxels == summary.observed_voxels);
      break;
    }
    case 3: {
      dds::Sample<semfuse_srv_dds__Objects_Request_> holder;
      const auto* request = decoded(holder, data, size);
      if (!request || (request->label != kUnlabeled && !legend().contains(request->label))) break;
      (void)server::findObjects(tinyMap(), legend(), request->label, request->min_voxels);
      break;
    }
    default: {
      dds::Sample<semfuse_srv_dds__Mesh_Request_> holder;
      const auto* request = decoded(holder, data, size);
      if (!request) break;
      render::MeshOptions options;
      if (request->use_box) {
        if (!validBox(toEigen(request->box_min), toEigen(request->box_max))) break;
        options.bounds = render::WorldBounds{toEigen(request->box_min), toEigen(request->box_max)};
      }
      (void)render::extractMesh(tinyMap(), options);
      break;
    }
  }
  return 0;
}
