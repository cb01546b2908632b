#include "app/app_smoothing.h"

namespace ripple::app {

void AddSmoothingOptions(CLI::App* sub, SmoothingArgs* args) {
  const tracking::SmoothingOptions d;
  sub->add_option("--smoothing", args->smoothing,
                  std::string("One Euro smoothing of the tank and pen poses: "
                              "on or off (default ") +
                      (d.enabled ? "on" : "off") + ")")
      ->check(CLI::IsMember({"on", "off"}));
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    return std::string(buf);
  };
  sub->add_option("--smooth-pen-hz", args->pen_hz,
                  "Smoothing: the pen tip's cut-off at rest, Hz (default " +
                      num(d.pen.min_cutoff_translation_hz) + ")");
  sub->add_option("--smooth-pen-beta", args->pen_beta,
                  "Smoothing: the pen tip's cut-off rise per speed, Hz per "
                  "m/s (default " +
                      num(d.pen.beta_translation_hz_per_m_s) + ")");
  sub->add_option("--smooth-pen-rot-hz", args->pen_rot_hz,
                  "Smoothing: the pen rotation's cut-off at rest, Hz "
                  "(default " +
                      num(d.pen.min_cutoff_rotation_hz) + ")");
  sub->add_option("--smooth-tank-hz", args->tank_hz,
                  "Smoothing: the tank's cut-off at rest, Hz (default " +
                      num(d.tank.min_cutoff_rotation_hz) + ")");
  sub->add_option("--smooth-max-lag", args->max_lag_s,
                  "Smoothing: bound on the lag behind a steady motion, "
                  "seconds (default " +
                      num(d.pen.max_lag_s) + ")");
  sub->add_option("--smooth-bridge-loss", args->bridge_loss_s,
                  "Smoothing: an object found again within this many seconds "
                  "goes on through its filter, 0 restarts it on every loss "
                  "(default " +
                      num(d.bridge_loss_s) + ")");
}

bool ApplySmoothingOptions(const SmoothingArgs& args,
                           tracking::SmoothingOptions* smoothing,
                           std::string* error) {
  auto set = [&](double v, const char* name, double* field) {
    if (std::isnan(v)) return true;
    if (!(v > 0) || !std::isfinite(v)) {
      if (error) *error = std::string(name) + " must be a positive number";
      return false;
    }
    *field = v;
    return true;
  };
  if (!args.smoothing.empty()) smoothing->enabled = args.smoothing == "on";
  if (!set(args.pen_hz, "--smooth-pen-hz",
           &smoothing->pen.min_cutoff_translation_hz) ||
      !set(args.pen_rot_hz, "--smooth-pen-rot-hz",
           &smoothing->pen.min_cutoff_rotation_hz) ||
      !set(args.tank_hz, "--smooth-tank-hz",
           &smoothing->tank.min_cutoff_rotation_hz) ||
      !set(args.tank_hz, "--smooth-tank-hz",
           &smoothing->tank.min_cutoff_translation_hz) ||
      !set(args.max_lag_s, "--smooth-max-lag", &smoothing->pen.max_lag_s) ||
      !set(args.max_lag_s, "--smooth-max-lag", &smoothing->tank.max_lag_s))
    return false;
  if (!std::isnan(args.pen_beta)) {
    if (!(args.pen_beta >= 0) || !std::isfinite(args.pen_beta)) {
      if (error) *error = "--smooth-pen-beta must be a number >= 0";
      return false;
    }
    smoothing->pen.beta_translation_hz_per_m_s = args.pen_beta;
  }
  if (!std::isnan(args.bridge_loss_s)) {
    if (!(args.bridge_loss_s >= 0) || !std::isfinite(args.bridge_loss_s)) {
      if (error) *error = "--smooth-bridge-loss must be a number >= 0";
      return false;
    }
    smoothing->bridge_loss_s = args.bridge_loss_s;
  }
  return smoothing->IsValid(error);
}

}  // namespace ripple::app
