// Options of the two water models and the choice between them.
#ifndef RIPPLE_SIM_WATER_OPTIONS_H_
#define RIPPLE_SIM_WATER_OPTIONS_H_

#include <optional>
#include <string>

#include "sim/dispersion.h"
#include "sim/water.h"

namespace ripple::sim {

enum class WaveModel {
  kCapillaryGravity,  // sim/spectral_water.h: real water's dispersion
  kPaper,             // sim/water.h: Tawara & Ono's constant-speed scheme
};

enum class PenModel {
  // The submerged shaft displaces its volume: entering raises the water
  // around it, leaving lowers it, moving pushes water ahead and draws it in
  // behind (ring waves and a wake).
  kDisplace,
  // The paper's Gaussian push: a downward acceleration under the tip while
  // it is below the surface, with a uniform compensation (volume kept).
  kPaperPush,
};

// "capillary" / "paper" and "displace" / "paper"; nullopt otherwise.
std::optional<WaveModel> ParseWaveModel(const std::string& name);
std::optional<PenModel> ParsePenModel(const std::string& name);
const char* WaveModelName(WaveModel model);
const char* PenModelName(PenModel model);

struct SpectralWaterOptions {
  // g, sigma/rho and nu; the depth H is the grid's rest level.
  CapillaryGravity physics;
  // Propagation and pen-sampling step, seconds: every mode is evolved
  // exactly over it (any value is stable); the pen's displacement changes
  // once per step.
  double substep_s = 1.0 / 240.0;
  // Waves shorter than this (metres) are not simulated: viscosity kills a
  // 3 mm ripple in 0.11 s and the pen's kernel barely excites them, so the
  // modal band (and the cost per sub-step) stays ~6x below the grid's.
  // The grid, not this, sets how finely the heights are drawn.
  double shortest_wavelength_m = 0.003;
  WallMode walls = WallMode::kReflect;
  // Absorbing walls: a sponge band this wide (metres) along the walls in
  // which waves are relaxed away over ~1/sponge_rate seconds.
  double sponge_width_m = 0.012;
  double sponge_rate_per_s = 40.0;
  // Obstacles and the sponge are imposed in the cell domain every this many
  // seconds (rounded to whole sub-steps): inside an obstacle the surface is
  // held at the mean level and still, so waves reflect from its edge.
  double boundary_step_s = 1.0 / 30.0;
  PenModel pen = PenModel::kDisplace;
  // Shaft radius, metres: the submerged volume is pi * r^2 * depth.
  double pen_shaft_radius_m = 0.005;
  // Submerged length is clamped to the shaft's length, metres.
  double pen_shaft_length_m = 0.125;
  // Push radius r, metres: the displacement (or push) is spread as a
  // Gaussian of standard deviation r/2 (a disc of radius r has that second
  // moment). It sets the dominant wavelength: small r, short waves.
  double pen_radius_m = 0.005;
  // Paper push only: acceleration under the tip, m/s^2, and its Gaussian's
  // standard deviation max(0.2*r, cell/2).
  double pen_strength_m_per_s2 = 5.0;
  // C in the shaft's surface pressure p/rho = C * U^2 / 2 (U its horizontal
  // speed, m/s); 1 is the stagnation pressure.
  double pen_pressure_coefficient = 1.0;
  // The displaced volume follows the shaft's depth at most this fast, m/s,
  // so a pen first seen already submerged (or a tracking jump) does not
  // splash.
  double pen_max_speed_m_per_s = 1.0;
  // A pen lost from view while submerged is withdrawn at this speed, m/s,
  // rather than vanishing at once (which would leave a hole in the water).
  double pen_withdraw_speed_m_per_s = 0.05;
  int max_substeps = 2000;  // per Advance(); the surplus time is dropped
  // Rest: when the modal speed bound <= rest_speed and max|h - mean| <=
  // rest_height and nothing touches the water, it is snapped flat.
  double rest_speed_m_per_s = 1e-3;
  double rest_height_m = 1e-5;

  bool IsValid(std::string* error) const;
};

struct WaterModelOptions {
  WaveModel waves = WaveModel::kCapillaryGravity;
  SpectralWaterOptions spectral;  // waves == kCapillaryGravity
  WaterOptions paper;             // waves == kPaper (pen: the paper's push)

  bool IsValid(std::string* error) const;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_WATER_OPTIONS_H_
