#pragma once
// The one check of a camera: pinhole intrinsics and a camera-to-world pose. Every place that
// takes a camera from outside (the wire, dataset files, queries, the volume, the renderers) uses
// it, with the same tolerance and the same messages, so that a camera accepted in one place is
// never refused in another. Callers put their context in front ("raycast ", "TUM RGB-D "); the
// messages start with what is wrong: "intrinsics: ..." or "pose: ...". Failures are
// ErrorCode::kInvalidArgument.
#include <cstdint>
#include <limits>

#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// |R^T R - I| (Frobenius) allowed: poses read from text files, like 7-Scenes', are orthonormal to
// ~2e-4 only, and that is still a rotation.
inline constexpr double kRotationTolerance = 1e-3;

// No limit on the image side (the wire sets one to bound what a message can allocate).
inline constexpr int kAnyImageSide = std::numeric_limits<int>::max();

// Largest image side a message or a query may carry: bounds every allocation a message can cause.
inline constexpr uint32_t kMaxImageSide = 8192;

// Focal lengths finite and > 0, principal point finite: the projection alone, for intrinsics
// read before the image size is known (a 7-Scenes camera-intrinsics.txt).
Status checkProjection(const PinholeIntrinsics& intrinsics);

// A non-empty image of at most max_side pixels a side, and checkProjection.
Status checkIntrinsics(const PinholeIntrinsics& intrinsics, int max_side = kAnyImageSide);

// A finite rigid transform: finite entries, bottom row [0 0 0 1], a rotation orthonormal within
// `tolerance` (the message gives the measured error) and not a reflection.
Status checkRigidPose(const Pose& pose, double tolerance = kRotationTolerance);

// checkIntrinsics, then checkRigidPose.
Status checkCamera(const PinholeIntrinsics& intrinsics, const Pose& camera_to_world, int max_side = kAnyImageSide);

}  // namespace semfuse
