#pragma once
// The list of every wire type of idl/, shared by the echo process and the round-trip test.
#include <string>

#include "semfuse/dds/type_support.hpp"

namespace semfuse::dds::testing {

template <class... T>
struct TypeList {};

using WireTypes =
    TypeList<builtin_interfaces_msg_dds__Time_, std_msgs_msg_dds__Header_, geometry_msgs_msg_dds__Vector3_,
             geometry_msgs_msg_dds__Point_, geometry_msgs_msg_dds__Quaternion_, geometry_msgs_msg_dds__Transform_,
             geometry_msgs_msg_dds__TransformStamped_, sensor_msgs_msg_dds__Image_,
             sensor_msgs_msg_dds__CompressedImage_, sensor_msgs_msg_dds__RegionOfInterest_,
             sensor_msgs_msg_dds__CameraInfo_, tf2_msgs_msg_dds__TFMessage_, semfuse_msg_dds__CameraIntrinsics_,
             semfuse_msg_dds__Frame_, semfuse_msg_dds__Segmentation_, semfuse_msg_dds__TrackedPose_,
             semfuse_msg_dds__Counter_, semfuse_msg_dds__CameraState_, semfuse_msg_dds__ErrorEntry_,
             semfuse_msg_dds__StageTiming_, semfuse_msg_dds__ServerStatus_, semfuse_msg_dds__LabelEntry_,
             semfuse_msg_dds__LabelLegend_, semfuse_msg_dds__VoxelSample_, semfuse_msg_dds__LabelCount_,
             semfuse_msg_dds__FrameRef_, semfuse_msg_dds__ObjectInstance_, semfuse_srv_dds__Raycast_Request_,
             semfuse_srv_dds__Raycast_Response_, semfuse_srv_dds__LabelsAt_Request_,
             semfuse_srv_dds__LabelsAt_Response_, semfuse_srv_dds__Region_Request_, semfuse_srv_dds__Region_Response_,
             semfuse_srv_dds__Objects_Request_, semfuse_srv_dds__Objects_Response_, semfuse_srv_dds__Mesh_Request_,
             semfuse_srv_dds__Mesh_Response_, semfuse_srv_dds__Admin_Request_, semfuse_srv_dds__Admin_Response_>;

inline constexpr int kWireTypeCount = 39;

// fn(Tag<T>{}) for every wire type.
template <class T>
struct Tag {
  using type = T;
};
template <class Fn, class... T>
void forEach(TypeList<T...>, Fn&& fn) {
  (fn(Tag<T>{}), ...);
}
template <class Fn>
void forEachWireType(Fn&& fn) {
  forEach(WireTypes{}, fn);
}

// "semfuse::msg::dds_::Frame_" -> "semfuse_msg_dds__Frame_" (topic names take no colons).
template <class T>
std::string topicSuffix() {
  std::string name = descriptorOf<T>().m_typename;
  std::string out;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (name[i] == ':' && i + 1 < name.size() && name[i + 1] == ':') {
      out += '_';
      ++i;
    } else {
      out += name[i];
    }
  }
  return out;
}

}  // namespace semfuse::dds::testing
