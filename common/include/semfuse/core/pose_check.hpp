#pragma once
// The one check that a camera-to-world pose is a finite rigid transform. Every place that takes a
// pose from outside (the wire, files, queries, the synthetic renderer) uses it, so that a pose
// accepted in one place is never refused in another.
#include "semfuse/core/result.hpp"
#include "semfuse/core/types.hpp"

namespace semfuse {

// |R^T R - I| (Frobenius) allowed: poses read from text files, like 7-Scenes', are orthonormal to
// ~2e-4 only, and that is still a rotation.
inline constexpr double kRotationTolerance = 1e-3;

// Fails, naming the problem ("pose: ..."), on a non-finite entry, a rotation that is not
// orthonormal within `tolerance`, or a reflection.
Status checkRigidPose(const Pose& pose, double tolerance = kRotationTolerance);

}  // namespace semfuse
