#include "calib/tip_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "calib/calib_io.h"

namespace ripple::calib {

std::vector<CheckPoint> BoardCheckPoints(const tracking::Rig& rig) {
  const double qx = 0.25 * rig.tank.size_x_m, qy = 0.25 * rig.tank.size_y_m;
  const Eigen::Vector3d candidates[5] = {
      {0, 0, 0}, {-qx, qy, 0}, {qx, qy, 0}, {qx, -qy, 0}, {-qx, -qy, 0}};
  std::vector<CheckPoint> points;
  for (const Eigen::Vector3d& p : candidates) {
    bool on_tag = false;
    for (const tracking::TagPlacement& t : rig.tank_tags) {
      const Eigen::Vector3d in_tag = t.object_from_tag.Inverse() * p;
      const double half = 0.5 * t.edge_m * (1.0 + 2.0 / 8.0);
      on_tag |= std::abs(in_tag.x()) < half && std::abs(in_tag.y()) < half;
    }
    if (!on_tag) points.push_back({"P" + std::to_string(points.size() + 1), p});
  }
  return points;
}

bool TipCheckOptions::IsValid(std::string* error) const {
  if (!(still_radius_m > 0) || !(min_still_s >= 0) || !(max_match_m > 0)) {
    if (error) *error = "tip check options must be positive";
    return false;
  }
  return true;
}

std::string TipCheckSummary::BriefReport() const {
  std::string s = "point  samples  error_mm  in_plane_mm  height_mm\n";
  char line[160];
  for (const TouchResult& t : touches) {
    std::snprintf(line, sizeof(line), "%-5s  %7d  %8.2f  %11.2f  %9.2f\n",
                  t.name.c_str(), t.samples, 1e3 * t.error_m,
                  1e3 * t.error_xy_m, 1e3 * t.error_z_m);
    s += line;
  }
  std::snprintf(line, sizeof(line), "tip error RMS %.2f mm, max %.2f mm\n",
                1e3 * rms_m, 1e3 * max_m);
  return s + line;
}

bool EvaluateTipCheck(const TipCheckOptions& options,
                      const std::vector<CheckPoint>& points,
                      const std::vector<TipSample>& samples,
                      TipCheckSummary* summary, std::string* error) {
  if (!options.IsValid(error)) return false;
  *summary = TipCheckSummary();
  std::vector<TouchResult> best(points.size());
  size_t i = 0;
  while (i < samples.size()) {
    Eigen::Vector3d sum = samples[i].tip_in_tank;
    size_t j = i + 1;
    for (; j < samples.size(); ++j) {
      const Eigen::Vector3d mean = sum / double(j - i);
      if ((samples[j].tip_in_tank - mean).norm() > options.still_radius_m)
        break;
      sum += samples[j].tip_in_tank;
    }
    const double duration = samples[j - 1].time_s - samples[i].time_s;
    if (duration >= options.min_still_s) {
      const Eigen::Vector3d mean = sum / double(j - i);
      int nearest = -1;
      double nearest_m = options.max_match_m;
      for (size_t p = 0; p < points.size(); ++p) {
        const double d = (mean - points[p].point_in_tank).norm();
        if (d < nearest_m) nearest_m = d, nearest = static_cast<int>(p);
      }
      if (nearest >= 0 && int(j - i) > best[nearest].samples) {
        TouchResult& t = best[nearest];
        t.name = points[nearest].name;
        t.point_in_tank = points[nearest].point_in_tank;
        t.measured_in_tank = mean;
        t.samples = static_cast<int>(j - i);
        t.start_s = samples[i].time_s;
        t.end_s = samples[j - 1].time_s;
        const Eigen::Vector3d d = mean - t.point_in_tank;
        t.error_m = d.norm();
        t.error_xy_m = d.head<2>().norm();
        t.error_z_m = d.z();
      }
    }
    i = j;
  }
  double sse = 0;
  for (const TouchResult& t : best) {
    if (t.samples == 0) continue;
    summary->touches.push_back(t);
    sse += t.error_m * t.error_m;
    summary->max_m = std::max(summary->max_m, t.error_m);
  }
  if (summary->touches.empty()) {
    *error =
        "no touch found: hold the tip still on a printed point (P1...) for at "
        "least " +
        std::to_string(options.min_still_s) + " s";
    return false;
  }
  summary->rms_m = std::sqrt(sse / summary->touches.size());
  return true;
}

bool WriteTipCheckCsv(const TipCheckSummary& summary, const std::string& path,
                      std::string* error) {
  return WriteAtomically(
      path,
      [&](const std::string& temp, std::string* e) {
        std::ofstream f(temp);
        f << "point,x_m,y_m,z_m,measured_x_m,measured_y_m,measured_z_m,"
             "samples,start_s,end_s,error_m,error_xy_m,error_z_m\n";
        for (const TouchResult& t : summary.touches) {
          char line[512];
          std::snprintf(line, sizeof(line),
                        "%s,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%d,%.3f,%.3f,%.5f,"
                        "%.5f,%.5f\n",
                        t.name.c_str(), t.point_in_tank.x(),
                        t.point_in_tank.y(), t.point_in_tank.z(),
                        t.measured_in_tank.x(), t.measured_in_tank.y(),
                        t.measured_in_tank.z(), t.samples, t.start_s, t.end_s,
                        t.error_m, t.error_xy_m, t.error_z_m);
          f << line;
        }
        f.close();
        if (!f) *e = "cannot write '" + path + "'";
        return static_cast<bool>(f);
      },
      error);
}

}  // namespace ripple::calib
