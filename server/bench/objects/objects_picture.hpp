#pragma once
// A picture of a map's objects: the map raycast from a given pose, every pixel coloured by the
// object its surface belongs to (one colour per id, shaded by the surface's normal), grey where
// the surface belongs to no object, and each object's class and id written where it is seen most.
#include <string>

#include "semfuse/core/legend.hpp"
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"
#include "semfuse/objects/object_tracker.hpp"
#include "semfuse/volume/labeled_volume.hpp"

namespace semfuse::bench {

struct ObjectsPicture {
  int objects_in_view = 0;  // objects (fragments not counted) with at least 100 pixels
  double covered = 0.0;     // share of the surface pixels that belong to an object
};

Result<ObjectsPicture> writeObjectsPicture(const volume::LabeledVolume& map, const objects::ObjectSet& objects,
                                           const LabelLegend& legend, const Pose& camera_to_world,
                                           const PinholeIntrinsics& intrinsics, const std::string& png_path);

// A 4x4 camera-to-world matrix, row by row (a 7-Scenes frame-*.pose.txt), made rigid.
Result<Pose> readPoseMatrix(const std::string& path);

}  // namespace semfuse::bench
