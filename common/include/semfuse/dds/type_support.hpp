#pragma once
// TypeSupport<T>: the Cyclone topic descriptor of each generated wire struct, so that the
// templates below can go from a C++ type to its descriptor without the caller naming it.
// Every struct of idl/ has one; a type without one fails to compile at its first use.
#include <dds/dds.h>

#include "builtin_interfaces.h"
#include "geometry_msgs.h"
#include "msg.h"
#include "nav_msgs.h"
#include "sensor_msgs.h"
#include "srv.h"
#include "std_msgs.h"
#include "tf2_msgs.h"
#include "visualization_msgs.h"

namespace semfuse::dds {

template <class T>
struct TypeSupport;  // no definition: only wire types are allowed

#define SEMFUSE_DDS_TYPE_SUPPORT(ctype)                                        \
  template <>                                                                  \
  struct TypeSupport<ctype> {                                                  \
    static const dds_topic_descriptor_t& descriptor() { return ctype##_desc; } \
  };

// ROS 2 standard types
SEMFUSE_DDS_TYPE_SUPPORT(builtin_interfaces_msg_dds__Time_)
SEMFUSE_DDS_TYPE_SUPPORT(std_msgs_msg_dds__Header_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__Vector3_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__Point_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__Quaternion_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__Transform_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__TransformStamped_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__Image_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__CompressedImage_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__RegionOfInterest_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__CameraInfo_)
SEMFUSE_DDS_TYPE_SUPPORT(tf2_msgs_msg_dds__TFMessage_)
SEMFUSE_DDS_TYPE_SUPPORT(geometry_msgs_msg_dds__Pose_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__PointField_)
SEMFUSE_DDS_TYPE_SUPPORT(sensor_msgs_msg_dds__PointCloud2_)
SEMFUSE_DDS_TYPE_SUPPORT(visualization_msgs_msg_dds__Marker_)
SEMFUSE_DDS_TYPE_SUPPORT(visualization_msgs_msg_dds__MarkerArray_)
SEMFUSE_DDS_TYPE_SUPPORT(nav_msgs_msg_dds__MapMetaData_)
SEMFUSE_DDS_TYPE_SUPPORT(nav_msgs_msg_dds__OccupancyGrid_)
// semfuse messages
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__CameraIntrinsics_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__Frame_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__Segmentation_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__TrackedPose_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__Counter_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__CameraState_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__ErrorEntry_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__StageTiming_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__ServerStatus_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__LabelEntry_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__LabelLegend_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__VoxelSample_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__LabelCount_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__FrameRef_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__ObjectInstance_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__MeshBlock_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__MapUpdate_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__ObjectEvent_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__ObjectEvents_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__DistanceSample_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__SemanticSample_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__Segment_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_msg_dds__SegmentResult_)
// semfuse services
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Raycast_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Raycast_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__LabelsAt_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__LabelsAt_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Region_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Region_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Objects_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Objects_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Mesh_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Mesh_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Admin_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Admin_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__MapBlocks_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__MapBlocks_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Distance_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__Distance_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__OccupancySlice_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__OccupancySlice_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SemanticDistance_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SemanticDistance_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SemanticSlice_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SemanticSlice_Response_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SegmentCheck_Request_)
SEMFUSE_DDS_TYPE_SUPPORT(semfuse_srv_dds__SegmentCheck_Response_)

#undef SEMFUSE_DDS_TYPE_SUPPORT

template <class T>
const dds_topic_descriptor_t& descriptorOf() {
  return TypeSupport<T>::descriptor();
}

}  // namespace semfuse::dds
