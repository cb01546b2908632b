// One Euro filter on rigid poses (Casiez, Roussel & Vogel, "1 Euro Filter: A
// Simple Speed-based Low-pass Filter for Noisy Input in Interactive Systems",
// CHI 2012): a first-order low-pass whose cut-off rises with the filtered
// speed, so that a pose at rest is smoothed hard and a moving one follows
// with little lag.
//
// The pose is filtered as a point and a rotation: the point is the image of
// `pivot_in_object` (the pen's tip, say), so that the rotation's lag does not
// move the point that matters; the rotation is filtered in the tangent space
// at the measurement (log map), the slerp of the One Euro step.
//
// Frame-rate independence: each step solves the continuous low-pass
// tau dx/dt = z - x exactly for a measurement moving linearly between two
// samples (first-order hold), so the same motion sampled at 30 or 60 fps
// gives the same output at the common times (exactly for piecewise-linear
// motion; the speed estimate that drives the cut-off adds an error of the
// order of dt). The lag behind a constant-velocity motion is then exactly
// tau = 1 / (2 pi fc), whatever dt.
//
// Guarantees, whatever the cut-offs:
//   - tau <= max_lag_s: the lag behind a steady motion is at most max_lag_s;
//   - a measurement farther than reset_translation_m or reset_rotation_deg
//     from the filtered pose restarts the filter at the measurement (a flip,
//     a re-acquisition or a cut is never smeared);
//   - Reset() (the caller's: on a cut, a long loss, an accepted jump) does
//     the same on the next sample.
//
// Growing memory (`growing_memory`, on by default): after a restart the time
// constant is capped by the time since the restart, so the first samples
// are weighted about equally (nearly their running mean, the least-squares
// estimate of a pose at rest) until the cut-off's own time constant is
// reached. A plain low-pass would hold the restart's single sample with
// weight about exp(-t / tau): 0.8-0.9 of the output a frame later at 1 Hz
// and 30 fps.
#ifndef RIPPLE_TRACKING_POSE_FILTER_H_
#define RIPPLE_TRACKING_POSE_FILTER_H_

#include <Eigen/Core>
#include <optional>
#include <string>

#include "tracking/pose.h"

namespace ripple::tracking {

struct PoseFilterOptions {
  // Cut-off at rest of the pivot's position and of the rotation (Hz).
  double min_cutoff_translation_hz = 1.0;
  double min_cutoff_rotation_hz = 1.0;
  // Cut-off increase per unit of filtered speed: Hz per (m/s) of the pivot,
  // Hz per (rad/s) of the rotation.
  double beta_translation_hz_per_m_s = 100.0;
  double beta_rotation_hz_per_rad_s = 2.0;
  // Cut-off of the speed estimate that drives the adaptation (Hz).
  double derivative_cutoff_hz = 1.0;
  // Bound on the steady lag behind a constant-velocity motion (seconds,
  // > 0).
  double max_lag_s = 0.25;
  // Cap the time constant by the time since the last restart (see above).
  bool growing_memory = true;
  // Restart at the measurement when it is farther than this from the
  // filtered pose (metres at the pivot; degrees).
  double reset_translation_m = 0.03;
  double reset_rotation_deg = 10.0;

  bool IsValid(std::string* error) const;
};

class PoseFilter {
 public:
  PoseFilter() = default;
  // `pivot_in_object`: the object point whose position is filtered
  // (metres, object frame).
  explicit PoseFilter(
      const PoseFilterOptions& options,
      const Eigen::Vector3d& pivot_in_object = Eigen::Vector3d::Zero())
      : options_(options), pivot_in_object_(pivot_in_object) {}

  // Filters `ref_from_object` measured at `time_s` (seconds). Returns the
  // measurement itself on the first sample after construction or Reset(),
  // when time does not advance, and on a jump beyond the reset bounds.
  Pose Filter(const Pose& ref_from_object, double time_s);
  void Reset() { state_.reset(); }
  // Whether the last Filter() call restarted the filter (first sample,
  // time not advancing, or a jump).
  bool restarted() const { return restarted_; }
  // The filtered speeds after the last sample: pivot (m/s), rotation
  // (rad/s); zero before the second sample.
  double speed_m_s() const {
    return state_ ? state_->rate.tail<3>().norm() : 0;
  }
  double speed_rad_s() const {
    return state_ ? state_->rate.head<3>().norm() : 0;
  }

 private:
  struct State {
    Eigen::Quaterniond rotation;       // filtered
    Eigen::Vector3d pivot;             // filtered, reference frame
    Eigen::Quaterniond raw_rotation;   // the last measurement
    Eigen::Vector3d raw_pivot;         // the last measurement
    Eigen::Matrix<double, 6, 1> rate;  // filtered speed: rad/s (3), m/s (3)
    double time_s = 0;
    double start_s = 0;  // of the last restart
  };
  Pose Restart(const Pose& ref_from_object, double time_s);

  PoseFilterOptions options_;
  Eigen::Vector3d pivot_in_object_ = Eigen::Vector3d::Zero();
  std::optional<State> state_;
  bool restarted_ = false;
};

// The smoothing factor of a first-order low-pass of cut-off `cutoff_hz` over
// `dt_s` seconds for an input held between samples: 1 - exp(-2 pi
// cutoff_hz dt_s).
double LowPassAlpha(double cutoff_hz, double dt_s);

// One step of the low-pass tau dx/dt = z - x over `dt_s` for an input moving
// linearly from `z_prev` to `z` (first-order hold), on offsets: given the
// filtered value's offset from the previous input, `x_prev - z_prev`, and the
// input's step `z - z_prev`, returns x - z.
Eigen::Vector3d LowPassStep(const Eigen::Vector3d& offset_prev,
                            const Eigen::Vector3d& input_step, double tau_s,
                            double dt_s);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_POSE_FILTER_H_
