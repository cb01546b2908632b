// Fixed sub-steps on an absolute time grid: a frame of any length runs the
// sub-steps that fall due in it, so results do not depend on the frame rate.
#ifndef RIPPLE_SIM_SUBSTEP_CLOCK_H_
#define RIPPLE_SIM_SUBSTEP_CLOCK_H_

#include <algorithm>
#include <cmath>

namespace ripple::sim {

struct SubstepClock {
  double accumulator_s = 0;  // time since the last sub-step boundary

  struct Due {
    int substeps = 0;      // to run now
    double dropped_s = 0;  // beyond max_substeps, dropped
    double end_s = 0;      // time of the last due sub-step's end
  };

  // A frame of dt_frame_s ending at now_s with sub-steps of step_s.
  Due Advance(double dt_frame_s, double now_s, double step_s,
              int max_substeps) {
    accumulator_s += dt_frame_s;
    const double due = std::floor(accumulator_s / step_s + 1e-7);
    Due d;
    d.substeps = static_cast<int>(std::min<double>(due, max_substeps));
    d.dropped_s = (due - d.substeps) * step_s;
    accumulator_s = std::max(0.0, accumulator_s - due * step_s);
    d.end_s = now_s - accumulator_s;
    return d;
  }
  // At rest: keep the phase so that later sub-steps stay on the same grid.
  void Idle(double dt_frame_s, double step_s) {
    accumulator_s = std::fmod(accumulator_s + dt_frame_s, step_s);
  }
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_SUBSTEP_CLOCK_H_
