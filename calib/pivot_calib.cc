#include "calib/pivot_calib.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ripple::calib {
namespace {

struct PivotCost {
  explicit PivotCost(const tracking::Pose& ref_from_pen) : pose(ref_from_pen) {}
  template <typename T>
  bool operator()(const T* tip, const T* pivot, T* residual) const {
    const Eigen::Matrix<T, 3, 1> p =
        pose.Cast<T>() * Eigen::Matrix<T, 3, 1>(tip[0], tip[1], tip[2]);
    for (int i = 0; i < 3; ++i) residual[i] = p[i] - pivot[i];
    return true;
  }
  tracking::Pose pose;
};

}  // namespace

bool PivotOptions::IsValid(std::string* error) const {
  if (min_views < 3) {
    if (error) *error = "min_views must be >= 3";
    return false;
  }
  if (!(min_spread_rad >= 0) || !(loss_scale_m > 0)) {
    if (error) *error = "min_spread_rad must be >= 0 and loss_scale_m > 0";
    return false;
  }
  return true;
}

std::string PivotSummary::BriefReport() const {
  char s[512];
  std::snprintf(s, sizeof(s),
                "pivot: %d views, rotation spread %.1f deg\n"
                "tip_in_pen [%.2f, %.2f, %.2f] mm, pivot [%.2f, %.2f, %.2f] "
                "mm\nresidual RMS %.2f mm, max %.2f mm\n",
                views, spread_rad * 180.0 / M_PI, 1e3 * tip_in_pen.x(),
                1e3 * tip_in_pen.y(), 1e3 * tip_in_pen.z(),
                1e3 * pivot_in_ref.x(), 1e3 * pivot_in_ref.y(),
                1e3 * pivot_in_ref.z(), 1e3 * rms_m, 1e3 * max_m);
  return s;
}

double RotationSpread(const std::vector<tracking::Pose>& ref_from_pen) {
  if (ref_from_pen.size() < 2) return 0;
  Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
  for (const auto& p : ref_from_pen) mean += p.R();
  mean /= ref_from_pen.size();
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (const auto& p : ref_from_pen) {
    const Eigen::Matrix3d d = p.R() - mean;
    m += d.transpose() * d;
  }
  m /= ref_from_pen.size();
  const double lambda =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m).eigenvalues()(0);
  return std::sqrt(std::max(lambda, 0.0));
}

bool CalibratePivot(const PivotOptions& options,
                    const std::vector<tracking::Pose>& ref_from_pen,
                    PivotSummary* summary, std::string* error) {
  if (!options.IsValid(error)) return false;
  *summary = PivotSummary();
  summary->views = static_cast<int>(ref_from_pen.size());
  if (summary->views < options.min_views) {
    *error = "too few views: the pen was tracked in " +
             std::to_string(summary->views) + " frames (need " +
             std::to_string(options.min_views) + ")";
    return false;
  }
  summary->spread_rad = RotationSpread(ref_from_pen);
  if (summary->spread_rad < options.min_spread_rad) {
    char s[256];
    std::snprintf(s, sizeof(s),
                  "degenerate motion: the pen rotated too little about two "
                  "axes (spread %.1f deg, need %.1f deg); tilt it in all "
                  "directions around the tip",
                  summary->spread_rad * 180.0 / M_PI,
                  options.min_spread_rad * 180.0 / M_PI);
    *error = s;
    return false;
  }
  // Linear start: [R_i  -I] [tip; pivot] = -t_i.
  const int n = summary->views;
  Eigen::MatrixXd a(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (int i = 0; i < n; ++i) {
    a.block<3, 3>(3 * i, 0) = ref_from_pen[i].R();
    a.block<3, 3>(3 * i, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * i) = -ref_from_pen[i].translation;
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
  double tip[3] = {x[0], x[1], x[2]};
  double pivot[3] = {x[3], x[4], x[5]};

  ceres::Problem problem;
  for (const auto& pose : ref_from_pen)
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<PivotCost, 3, 3, 3>(
            new PivotCost(pose)),
        new ceres::HuberLoss(options.loss_scale_m), tip, pivot);
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 50;
  solver.function_tolerance = 1e-14;
  solver.parameter_tolerance = 1e-14;
  ceres::Solver::Summary result;
  ceres::Solve(solver, &problem, &result);
  if (result.termination_type == ceres::FAILURE) {
    *error = "pivot fit failed: " + result.message;
    return false;
  }
  summary->tip_in_pen = Eigen::Vector3d(tip[0], tip[1], tip[2]);
  summary->pivot_in_ref = Eigen::Vector3d(pivot[0], pivot[1], pivot[2]);
  double sse = 0;
  for (const auto& pose : ref_from_pen) {
    const double r =
        (pose * summary->tip_in_pen - summary->pivot_in_ref).norm();
    summary->residuals_m.push_back(r);
    summary->max_m = std::max(summary->max_m, r);
    sse += r * r;
  }
  summary->rms_m = std::sqrt(sse / n);
  return true;
}

}  // namespace ripple::calib
