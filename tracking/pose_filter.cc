#include "tracking/pose_filter.h"

#include <algorithm>
#include <cmath>

namespace ripple::tracking {
namespace {

constexpr double kFilterRadPerDeg = M_PI / 180.0;

// Rotation vector of `q` (rad), the shorter way round.
Eigen::Vector3d Log(const Eigen::Quaterniond& q) {
  Eigen::AngleAxisd aa(q.w() < 0 ? Eigen::Quaterniond(-q.coeffs()) : q);
  return aa.angle() * aa.axis();
}

Eigen::Quaterniond Exp(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-15) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, v / angle));
}

}  // namespace

double LowPassAlpha(double cutoff_hz, double dt_s) {
  return 1.0 - std::exp(-2.0 * M_PI * cutoff_hz * dt_s);
}

Eigen::Vector3d LowPassStep(const Eigen::Vector3d& offset_prev,
                            const Eigen::Vector3d& input_step, double tau_s,
                            double dt_s) {
  // x(t) = z(t) - s tau + (x0 - z0 + s tau) exp(-t / tau) for z(t) = z0 + s t.
  const double q = std::exp(-dt_s / tau_s);
  return q * offset_prev - (tau_s / dt_s) * (1.0 - q) * input_step;
}

bool PoseFilterOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(min_cutoff_translation_hz > 0 && min_cutoff_rotation_hz > 0))
    return fail("smoothing min cut-offs must be positive (Hz)");
  if (!(beta_translation_hz_per_m_s >= 0 && beta_rotation_hz_per_rad_s >= 0))
    return fail("smoothing betas must be >= 0");
  if (!(derivative_cutoff_hz > 0))
    return fail("smoothing derivative cut-off must be positive (Hz)");
  if (!(max_lag_s > 0)) return fail("smoothing max lag must be positive (s)");
  if (!(reset_translation_m > 0 && reset_rotation_deg > 0))
    return fail("smoothing reset bounds must be positive");
  return true;
}

Pose PoseFilter::Restart(const Pose& ref_from_object, double time_s) {
  const Eigen::Vector3d pivot = ref_from_object * pivot_in_object_;
  state_ = State{ref_from_object.rotation,
                 pivot,
                 ref_from_object.rotation,
                 pivot,
                 Eigen::Matrix<double, 6, 1>::Zero(),
                 time_s,
                 time_s};
  restarted_ = true;
  return ref_from_object;
}

Pose PoseFilter::Filter(const Pose& ref_from_object, double time_s) {
  if (!state_ || !(time_s > state_->time_s))
    return Restart(ref_from_object, time_s);
  State& s = *state_;
  const double dt = time_s - s.time_s;
  const Eigen::Quaterniond& z_rotation = ref_from_object.rotation;
  const Eigen::Vector3d z_pivot = ref_from_object * pivot_in_object_;
  // A jump away from the filtered pose restarts.
  if (Log(z_rotation * s.rotation.conjugate()).norm() >
          options_.reset_rotation_deg * kFilterRadPerDeg ||
      (z_pivot - s.pivot).norm() > options_.reset_translation_m)
    return Restart(ref_from_object, time_s);
  restarted_ = false;
  // The measurement's step since the last one: rotation vector (reference
  // frame) and pivot displacement.
  const Eigen::Vector3d step_r = Log(z_rotation * s.raw_rotation.conjugate());
  const Eigen::Vector3d step_t = z_pivot - s.raw_pivot;
  Eigen::Matrix<double, 6, 1> rate;
  rate << step_r / dt, step_t / dt;
  s.rate += LowPassAlpha(options_.derivative_cutoff_hz, dt) * (rate - s.rate);
  // A growing memory after a restart: the time constant is at most the
  // time since the restart.
  const double max_tau = options_.growing_memory
                             ? std::min(options_.max_lag_s, time_s - s.start_s)
                             : options_.max_lag_s;
  auto tau = [&](double min_cutoff_hz, double beta, double speed) {
    const double cutoff = min_cutoff_hz + beta * speed;
    return std::min(1.0 / (2.0 * M_PI * cutoff), max_tau);
  };
  const double tau_r =
      tau(options_.min_cutoff_rotation_hz, options_.beta_rotation_hz_per_rad_s,
          s.rate.head<3>().norm());
  const double tau_t =
      tau(options_.min_cutoff_translation_hz,
          options_.beta_translation_hz_per_m_s, s.rate.tail<3>().norm());
  const Eigen::Vector3d offset_r = LowPassStep(
      Log(s.rotation * s.raw_rotation.conjugate()), step_r, tau_r, dt);
  const Eigen::Vector3d offset_t =
      LowPassStep(s.pivot - s.raw_pivot, step_t, tau_t, dt);
  s.rotation = (Exp(offset_r) * z_rotation).normalized();
  s.pivot = z_pivot + offset_t;
  s.raw_rotation = z_rotation;
  s.raw_pivot = z_pivot;
  s.time_s = time_s;
  Pose out;
  out.rotation = s.rotation;
  out.translation = s.pivot - s.rotation * pivot_in_object_;
  return out;
}

}  // namespace ripple::tracking
