#include "tracking/pose_filter.h"

#include <algorithm>
#include <cmath>

namespace ripple::tracking {
namespace {

double Alpha(double cutoff_hz, double dt_s) {
  const double tau = 1.0 / (2.0 * M_PI * cutoff_hz);
  return 1.0 / (1.0 + tau / dt_s);
}

}  // namespace

bool PoseFilterOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(min_cutoff_hz > 0)) return fail("min_cutoff_hz must be positive");
  if (!(beta_translation >= 0 && beta_rotation >= 0))
    return fail("beta must be >= 0");
  if (!(derivative_cutoff_hz > 0))
    return fail("derivative_cutoff_hz must be positive");
  if (!(max_lag_frames > 0)) return fail("max_lag_frames must be positive");
  return true;
}

Pose PoseFilter::Filter(const Pose& pose, double time_s) {
  if (!options_.enabled) return pose;
  if (!state_ || !(time_s > state_->time_s)) {
    state_ = State{pose, Eigen::Matrix<double, 6, 1>::Zero(), time_s};
    return pose;
  }
  State& s = *state_;
  const double dt = time_s - s.time_s;
  // Innovation: rotation vector (camera frame) and translation difference.
  const Eigen::AngleAxisd aa(pose.rotation * s.pose.rotation.conjugate());
  Eigen::Vector3d omega = aa.angle() * aa.axis();
  if (aa.angle() > M_PI) omega = (aa.angle() - 2 * M_PI) * aa.axis();
  const Eigen::Vector3d dtrans = pose.translation - s.pose.translation;
  Eigen::Matrix<double, 6, 1> rate;
  rate << omega / dt, dtrans / dt;
  const double a_d = Alpha(options_.derivative_cutoff_hz, dt);
  s.rate += a_d * (rate - s.rate);
  const double min_alpha = 1.0 / (1.0 + options_.max_lag_frames);
  const double cutoff_r =
      options_.min_cutoff_hz + options_.beta_rotation * s.rate.head<3>().norm();
  const double cutoff_t = options_.min_cutoff_hz +
                          options_.beta_translation * s.rate.tail<3>().norm();
  const double a_r = std::max(min_alpha, Alpha(cutoff_r, dt));
  const double a_t = std::max(min_alpha, Alpha(cutoff_t, dt));
  const Eigen::Vector3d step = a_r * omega;
  Eigen::Quaterniond dq = Eigen::Quaterniond::Identity();
  if (step.norm() > 1e-15)
    dq = Eigen::Quaterniond(Eigen::AngleAxisd(step.norm(), step.normalized()));
  s.pose.rotation = (dq * s.pose.rotation).normalized();
  s.pose.translation += a_t * dtrans;
  s.time_s = time_s;
  return s.pose;
}

}  // namespace ripple::tracking
