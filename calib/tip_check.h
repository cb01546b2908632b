// The tip check: the user touches the points printed on the board sheet
// with the pen tip; each still touch is matched to the nearest printed point
// and its error reported. This is what tells a real user how accurate their
// camera, rig and tip calibration are together.
#ifndef RIPPLE_CALIB_TIP_CHECK_H_
#define RIPPLE_CALIB_TIP_CHECK_H_

#include <Eigen/Core>
#include <string>
#include <vector>

#include "tracking/rig.h"

namespace ripple::calib {

// A marked point of the board sheet (a crosshair with its name).
struct CheckPoint {
  std::string name;               // "P1", ...
  Eigen::Vector3d point_in_tank;  // on the board, z = 0
};

// The points `ripple markers` prints on the board: the tank centre and the
// four points at (+-size_x/4, +-size_y/4), leaving out any that would fall on
// a tag (tag square plus one tag cell of margin).
std::vector<CheckPoint> BoardCheckPoints(const tracking::Rig& rig);

struct TipSample {
  double time_s = 0;
  Eigen::Vector3d tip_in_tank = Eigen::Vector3d::Zero();
};

struct TipCheckOptions {
  // Samples within this distance of the running mean of a touch belong to
  // it (metres).
  double still_radius_m = 0.004;
  double min_still_s = 0.4;  // a touch lasts at least this long, seconds
  // A touch is matched to the nearest check point within this distance,
  // metres (half the spacing of the printed points or less).
  double max_match_m = 0.02;

  bool IsValid(std::string* error) const;
};

struct TouchResult {
  std::string name;
  Eigen::Vector3d point_in_tank = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured_in_tank = Eigen::Vector3d::Zero();  // mean
  int samples = 0;
  double start_s = 0, end_s = 0;
  double error_m = 0;     // |measured - point|
  double error_xy_m = 0;  // in the board plane
  double error_z_m = 0;   // signed height above the board
};

struct TipCheckSummary {
  std::vector<TouchResult> touches;  // in the order of `points`
  double rms_m = 0, max_m = 0;
  std::string BriefReport() const;
};

// Finds still touches in the tip track and matches each to a point (the
// longest touch per point wins). False with `error` when no touch matched.
bool EvaluateTipCheck(const TipCheckOptions& options,
                      const std::vector<CheckPoint>& points,
                      const std::vector<TipSample>& samples,
                      TipCheckSummary* summary, std::string* error);

// Writes the touches as CSV (header point,x_m,...,error_z_m; one row per
// touch) to `path`, atomically (calib/calib_io.h). False with `error`.
bool WriteTipCheckCsv(const TipCheckSummary& summary, const std::string& path,
                      std::string* error);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_TIP_CHECK_H_
