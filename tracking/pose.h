// The tracker's pose type: geometry::Rigid3 (geometry/rigid3.h). Naming: a
// Pose variable called `a_from_b` maps a point expressed in frame b into
// frame a:
//   p_in_a = a_from_b * p_in_b.
#ifndef RIPPLE_TRACKING_POSE_H_
#define RIPPLE_TRACKING_POSE_H_

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/rigid3.h"

namespace ripple::tracking {

template <typename T>
using Rigid3 = geometry::Rigid3<T>;
using Pose = geometry::Rigid3d;
using geometry::RotationDistance;
using geometry::TranslationDistance;

// Pose with the camera at `eye` looking at `target`; `up` is a rough up
// direction in the world. Returns world_from_cam in the OpenCV camera
// convention (x right, y down, z forward).
Pose LookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& target,
            const Eigen::Vector3d& up);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_POSE_H_
