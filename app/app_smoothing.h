// The pose smoothing options (tracking::SmoothingOptions) on the command
// line, shared by track, live, replay and demo: --smoothing on|off and the
// filters' cut-offs, units in the help text.
#ifndef RIPPLE_APP_APP_SMOOTHING_H_
#define RIPPLE_APP_APP_SMOOTHING_H_

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

#include "tracking/tracker.h"

namespace ripple::app {

struct SmoothingArgs {
  std::string smoothing;  // "on", "off"; empty: the tracker's default
  // NaN: the default of tracking::SmoothingOptions.
  double pen_hz = std::nan("");         // pen tip's cut-off at rest, Hz
  double pen_beta = std::nan("");       // Hz per (m/s) of tip speed
  double pen_rot_hz = std::nan("");     // pen rotation's cut-off at rest, Hz
  double tank_hz = std::nan("");        // tank's cut-off at rest, Hz
  double max_lag_s = std::nan("");      // both filters' lag bound, s
  double bridge_loss_s = std::nan("");  // a loss the filters outlive, s
};

void AddSmoothingOptions(CLI::App* sub, SmoothingArgs* args);

// Applies the given options to `smoothing`; false with `error` naming the
// option for a bad value.
bool ApplySmoothingOptions(const SmoothingArgs& args,
                           tracking::SmoothingOptions* smoothing,
                           std::string* error);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_SMOOTHING_H_
