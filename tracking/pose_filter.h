// One Euro filter on rigid poses (Casiez, Roussel & Vogel, "1 Euro Filter: A
// Simple Speed-based Low-pass Filter for Noisy Input in Interactive Systems",
// CHI 2012), with the smoothing factor bounded so that the filter lags a
// steady motion by at most `max_lag_frames` frames.
//
// An exponential filter x += alpha (z - x) follows a ramp with a steady lag
// of (1 - alpha) / alpha samples, so alpha >= 1 / (1 + max_lag_frames)
// bounds the lag whatever the cut-off frequencies say.
#ifndef RIPPLE_TRACKING_POSE_FILTER_H_
#define RIPPLE_TRACKING_POSE_FILTER_H_

#include <optional>
#include <string>

#include "tracking/pose.h"

namespace ripple::tracking {

struct PoseFilterOptions {
  bool enabled = false;
  double min_cutoff_hz = 1.5;  // cut-off at rest
  // Cut-off increase per unit speed: Hz per (m/s) and per (rad/s).
  double beta_translation = 40.0;
  double beta_rotation = 0.5;
  double derivative_cutoff_hz = 1.0;
  double max_lag_frames = 1.0;  // bound on the steady lag, frames (> 0)

  bool IsValid(std::string* error) const;
};

class PoseFilter {
 public:
  PoseFilter() = default;
  explicit PoseFilter(const PoseFilterOptions& options) : options_(options) {}
  // Filters the pose observed at `time_s`; passes it through when disabled,
  // on the first sample, or when time does not advance.
  Pose Filter(const Pose& pose, double time_s);
  void Reset() { state_.reset(); }

 private:
  struct State {
    Pose pose;
    Eigen::Matrix<double, 6, 1> rate = Eigen::Matrix<double, 6, 1>::Zero();
    double time_s = 0;
  };
  PoseFilterOptions options_;
  std::optional<State> state_;
};

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_POSE_FILTER_H_
