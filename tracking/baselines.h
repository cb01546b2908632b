// Baseline pose methods for `ripple bench tracking`, each fed the same
// corrected and undistorted corners as the tracker (TagObservation), so that
// the comparison isolates the pose method.
#ifndef RIPPLE_TRACKING_BASELINES_H_
#define RIPPLE_TRACKING_BASELINES_H_

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "tracking/camera.h"
#include "tracking/object_pose.h"
#include "tracking/pose.h"

namespace ripple::tracking {

// The paper's method: the single tag most nearly facing the camera, posed
// with libapriltag's estimate_tag_pose (homography, then orthogonal
// iteration, keeping the lower object-space error of its two solutions).
std::optional<Pose> PaperFrontalTagPose(
    const Camera& camera, const std::vector<TagObservation>& observations);

// OpenCV solvePnP(SOLVEPNP_IPPE_SQUARE) on the best-posed tag: the one
// whose pose leaves the least uncertainty on `point_in_object` (the pen tip;
// the board centre for the tank), see PointUncertainty.
std::optional<Pose> OpenCvIppeBestTagPose(
    const Camera& camera, const std::vector<TagObservation>& observations,
    const Eigen::Vector3d& point_in_object);

// OpenCV SOLVEPNP_SQPNP over every visible corner of the object, then
// solvePnPRefineLM (what apriltag_ros' tag bundles do).
std::optional<Pose> SqpnpLmPose(
    const Camera& camera, const std::vector<TagObservation>& observations);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_BASELINES_H_
