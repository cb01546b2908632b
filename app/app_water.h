// The water's command-line options, shared by every command that runs the
// simulation (live, replay, demo, sim): the wave model, the pen model and
// their parameters with units, resolved against the rig (depth, shaft).
#ifndef RIPPLE_APP_APP_WATER_H_
#define RIPPLE_APP_APP_WATER_H_

#include <CLI/CLI.hpp>
#include <string>

#include "sim/water_options.h"
#include "tracking/rig.h"

namespace ripple::app {

struct WaterArgs {
  std::string waves = "capillary";  // capillary | paper
  std::string pen;  // displace | paper; empty: the model's (displace, paper)
  int cells = 0;    // along tank x; 0: the model's default
  std::string walls = "reflect";  // reflect | absorb
  // Model parameters; those not given keep the model's defaults. Each
  // belongs to one model and is refused with the other.
  struct Value {
    double value = 0;
    bool given = false;
  };
  Value viscosity_m2_per_s;  // capillary: kinematic viscosity nu
  Value damping_per_s;       // paper: velocity damping
  Value wave_speed_m_per_s;  // paper: c
  Value radius_m;            // both: push radius
  Value force_m_per_s2;      // paper push (either model)
};

// Adds --waves, --pen, --sim-cells, --walls, --viscosity, --damping,
// --wave-speed, --radius, --force to `sub`.
void AddWaterOptions(CLI::App* sub, WaterArgs* args);

// The model's options and cells along x (0 resolved to the model's
// default). False with one line naming the option on an unknown name, a
// value out of range or a parameter that belongs to the other model.
bool ResolveWaterOptions(const WaterArgs& args, sim::WaterModelOptions* options,
                         int* cells, std::string* error);

// Fits the options to the rig (the shaft's radius and length; the push
// radius follows the shaft unless `keep_radius`) and makes the grid for its
// tank (depth = water level). False with a line on a bad grid.
bool WaterForRig(const tracking::Rig& rig, int cells, bool keep_radius,
                 sim::WaterModelOptions* options, sim::GridSpec* grid,
                 std::string* error);

// Default cells along x: 256 for the capillary model (4 mm ripples), 128 for
// the paper's.
int DefaultWaterCells(sim::WaveModel model);

}  // namespace ripple::app

#endif  // RIPPLE_APP_APP_WATER_H_
