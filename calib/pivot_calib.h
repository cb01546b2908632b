// Pen-tip pivot calibration: the user pivots the pen about its tip, held in
// a dimple, while the camera tracks the cube. Every pose then maps the same
// unknown tip_in_pen onto the same unknown pivot point:
//   ref_from_pen_i * tip_in_pen = pivot_in_ref   for every view i,
// with ref the camera (a still camera) or the tank (the board in view).
// Linear least squares gives the start; Ceres refines it with a Huber loss
// that keeps a few bad poses from pulling the fit.
#ifndef RIPPLE_CALIB_PIVOT_CALIB_H_
#define RIPPLE_CALIB_PIVOT_CALIB_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "tracking/pose.h"

namespace ripple::calib {

struct PivotOptions {
  int min_views = 15;  // fewer poses: "too few views"
  // The pose rotations must spread at least this much (radians, RMS about
  // the worst-constrained tip direction, see PivotSummary::spread_rad):
  // pivoting about one axis only leaves the tip along that axis unknown.
  double min_spread_rad = 8.0 * M_PI / 180.0;
  double loss_scale_m = 0.002;  // Huber scale of the point residual, metres

  bool IsValid(std::string* error) const;
};

struct PivotSummary {
  int views = 0;
  Eigen::Vector3d tip_in_pen = Eigen::Vector3d::Zero();    // metres
  Eigen::Vector3d pivot_in_ref = Eigen::Vector3d::Zero();  // metres
  double rms_m = 0;  // RMS of |ref_from_pen_i * tip - pivot|, metres
  double max_m = 0;
  // sqrt(smallest eigenvalue of mean_i (R_i - R_mean)^T (R_i - R_mean)):
  // about the RMS rotation (radians) about the worst-constrained direction.
  double spread_rad = 0;
  std::vector<double> residuals_m;  // per view
  std::string BriefReport() const;
};

// Rotation spread of a pose set (see PivotSummary::spread_rad).
double RotationSpread(const std::vector<tracking::Pose>& ref_from_pen);

// False with `error` on too few views or too little rotation (degenerate
// motion); `summary` is filled as far as it got.
bool CalibratePivot(const PivotOptions& options,
                    const std::vector<tracking::Pose>& ref_from_pen,
                    PivotSummary* summary, std::string* error);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_PIVOT_CALIB_H_
