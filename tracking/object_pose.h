// Pose of one rigid object (the tank board or the pen cube) from the tags
// detected on it: IPPE initialisation (both branches of every tag square) and
// Ceres refinement of the reprojection error of every corner of every
// visible tag at once, through the full lens model, with a robust loss.
#ifndef RIPPLE_TRACKING_OBJECT_POSE_H_
#define RIPPLE_TRACKING_OBJECT_POSE_H_

#include <Eigen/Core>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"

namespace ripple::tracking {

// One detected tag matched to its placement on an object.
struct TagObservation {
  int id = -1;
  double edge_m = 0;
  Pose object_from_tag;
  std::array<Eigen::Vector3d, 4> corners_in_object;  // TL, TR, BR, BL
  std::array<Eigen::Vector2d, 4> pixels;      // distorted, OpenCV convention
  std::array<Eigen::Vector2d, 4> normalized;  // undistorted, z = 1 plane
  double size_px = 0;                         // mean edge length in the image
  // Corners the detector found hidden (TagDetection::corner_occluded): left
  // out of every error and fit below.
  std::array<bool, 4> occluded{false, false, false, false};
};

// Matches detections to the object's tags (unknown ids are skipped) and
// undistorts their corners. Hidden corners stay marked as long as at least
// three corners of the object are left (three fix a pose, though the
// tracker reports none from fewer than four); otherwise all are used.
std::vector<TagObservation> MatchObservations(
    const Camera& camera, const std::vector<TagPlacement>& tags,
    const std::vector<TagDetection>& detections);

enum class RobustLoss { kNone, kHuber, kCauchy };

struct PoseEstimatorOptions {
  bool refine = true;  // Ceres refinement; off: the best IPPE candidate
  RobustLoss loss = RobustLoss::kHuber;
  double loss_scale_px = 1.0;  // residual (pixels) where the loss turns robust
  int max_iterations = 20;
  // IPPE candidates come from the this many largest tags (both branches
  // each); every candidate is scored on all corners.
  int max_init_tags = 3;
  // A candidate more than `distinct_deg` away from the best whose IPPE error
  // is within `ambiguity_ratio` of it is refined as well, and the lower final
  // cost wins (the two-fold ambiguity of a single square).
  double distinct_deg = 10.0;
  double ambiguity_ratio = 4.0;
  // Weight each tag's corners by cos^2 of its viewing angle (at the starting
  // pose): corners of a tag seen edge-on are localised worse (foreshortened
  // cells, blur across the short edges), so a face at grazing incidence
  // should not pull a multi-face pose as hard as a frontal one.
  bool weight_by_view_angle = true;

  bool IsValid(std::string* error) const;
};

struct ObjectPose {
  Pose cam_from_object;
  double rmse_px = 0;        // RMS corner reprojection error, distorted pixels
  double sse_px2 = 0;        // sum of squared corner errors, pixels^2
  std::vector<int> tag_ids;  // tags used, ascending
  int num_corners = 0;
  int iterations = 0;  // Ceres iterations (0 without refinement)
  // Error of the best pose more than distinct_deg away (the other branch of
  // an ambiguous square); infinity when none was found.
  double alternative_rmse_px = std::numeric_limits<double>::infinity();
  // That pose, refined, when it was close enough to be refined as well (an
  // ambiguous view: ambiguity_ratio).
  std::optional<Pose> alternative;
};

// Estimates cam_from_object from `observations` (at least one tag). Extra
// starting poses (e.g. the previous frame's) join the IPPE candidates. False
// when there is nothing to estimate from or no candidate lies in front of
// the camera.
bool EstimateObjectPose(const PoseEstimatorOptions& options,
                        const Camera& camera,
                        const std::vector<TagObservation>& observations,
                        const std::vector<Pose>& extra_candidates,
                        ObjectPose* out);

// Refines from `initial` only (no IPPE); with options.refine off it just
// scores `initial`.
bool RefineObjectPose(const PoseEstimatorOptions& options, const Camera& camera,
                      const std::vector<TagObservation>& observations,
                      const Pose& initial, ObjectPose* out);

// The two IPPE solutions (Collins & Bartoli 2014, via OpenCV's
// SOLVEPNP_IPPE_SQUARE) for one tag, as cam_from_tag, best first.
std::vector<Pose> IppeSquare(const TagObservation& tag, double edge_m);

// Reprojection error of a pose: sum of squared corner errors (pixels^2,
// through the distortion model) and the number of corners.
double ReprojectionSse(const Camera& camera,
                       const std::vector<TagObservation>& observations,
                       const Pose& cam_from_object, int* num_corners);

// Standard deviation (metres; square root of the covariance trace) of
// `point_in_object` in the camera frame under 1 px isotropic corner noise,
// from the Gauss-Newton covariance (J^T J)^-1 of the pose at
// `cam_from_object`. Infinity when the pose is not constrained.
double PointUncertainty(const Camera& camera,
                        const std::vector<TagObservation>& observations,
                        const Pose& cam_from_object,
                        const Eigen::Vector3d& point_in_object);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_OBJECT_POSE_H_
