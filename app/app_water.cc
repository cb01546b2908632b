#include "app/app_water.h"

#include <cmath>

#include "sim/water_factory.h"

namespace ripple::app {

namespace {

// A number option whose presence is recorded; NaN and infinities are
// refused by the model's own range checks.
void AddValue(CLI::App* sub, const std::string& name, WaterArgs::Value* v,
              const std::string& help) {
  sub->add_option_function<double>(
      name,
      [v](const double& x) {
        v->value = x;
        v->given = true;
      },
      help);
}

}  // namespace

void AddWaterOptions(CLI::App* sub, WaterArgs* args) {
  sub->add_option("--waves", args->waves,
                  "Wave model: capillary (capillary-gravity dispersion, "
                  "default) or paper (Tawara & Ono's constant-speed scheme)")
      ->capture_default_str();
  sub->add_option("--pen", args->pen,
                  "Pen model: displace (the shaft's volume and motion push "
                  "the water, default) or paper (Gaussian push)")
      ->capture_default_str();
  sub->add_option("--sim-cells", args->cells,
                  "Water cells along the tank's long side (0: 256 for "
                  "capillary, 128 for paper)")
      ->capture_default_str();
  sub->add_option("--walls", args->walls, "Tank walls: reflect or absorb")
      ->capture_default_str();
  AddValue(sub, "--viscosity", &args->viscosity_m2_per_s,
           "Kinematic viscosity nu, m^2/s (capillary model; water "
           "1e-6, honey ~1e-2)");
  AddValue(sub, "--damping", &args->damping_per_s,
           "Velocity damping, 1/s (paper model)");
  AddValue(sub, "--wave-speed", &args->wave_speed_m_per_s,
           "Wave speed c, m/s (paper model)");
  AddValue(sub, "--radius", &args->radius_m,
           "Pen push radius r, m (small r: short waves)");
  AddValue(sub, "--force", &args->force_m_per_s2,
           "Paper push strength, m/s^2 (--pen paper)");
}

int DefaultWaterCells(sim::WaveModel model) {
  return model == sim::WaveModel::kCapillaryGravity ? 256 : 128;
}

bool ResolveWaterOptions(const WaterArgs& args, sim::WaterModelOptions* options,
                         int* cells, std::string* error) {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  const auto waves = sim::ParseWaveModel(args.waves);
  if (!waves)
    return fail("--waves '" + args.waves + "': use capillary or paper");
  const std::string pen_name =
      !args.pen.empty()
          ? args.pen
          : (*waves == sim::WaveModel::kPaper ? "paper" : "displace");
  const auto pen = sim::ParsePenModel(pen_name);
  if (!pen) return fail("--pen '" + args.pen + "': use displace or paper");
  if (args.walls != "reflect" && args.walls != "absorb")
    return fail("--walls '" + args.walls + "': use reflect or absorb");
  const sim::WallMode walls =
      args.walls == "absorb" ? sim::WallMode::kAbsorb : sim::WallMode::kReflect;
  auto set = [](const WaterArgs::Value& v) { return v.given; };
  sim::WaterModelOptions o;
  o.waves = *waves;
  std::string why;
  if (*waves == sim::WaveModel::kPaper) {
    if (*pen != sim::PenModel::kPaperPush)
      return fail(
          "--pen displace needs --waves capillary (the paper's "
          "scheme has the paper push only)");
    if (set(args.viscosity_m2_per_s))
      return fail(
          "--viscosity is the capillary model's (m^2/s); the paper "
          "model's is --damping (1/s)");
    o.paper.walls = walls;
    if (set(args.damping_per_s))
      o.paper.viscosity_per_s = args.damping_per_s.value;
    if (set(args.wave_speed_m_per_s))
      o.paper.wave_speed_m_per_s = args.wave_speed_m_per_s.value;
    if (set(args.radius_m)) o.paper.pen_radius_m = args.radius_m.value;
    if (set(args.force_m_per_s2))
      o.paper.pen_strength_m_per_s2 = args.force_m_per_s2.value;
    if (!o.paper.IsValid(&why)) return fail("water options: " + why);
  } else {
    if (set(args.damping_per_s))
      return fail("--damping is the paper model's; use --viscosity (m^2/s)");
    if (set(args.wave_speed_m_per_s))
      return fail(
          "--wave-speed is the paper model's; capillary waves run "
          "at the speed their wavelength gives");
    sim::SpectralWaterOptions& s = o.spectral;
    s.pen = *pen;
    s.walls = walls;
    if (set(args.viscosity_m2_per_s))
      s.physics.kinematic_viscosity_m2_per_s = args.viscosity_m2_per_s.value;
    if (set(args.radius_m)) s.pen_radius_m = args.radius_m.value;
    if (set(args.force_m_per_s2)) {
      if (s.pen != sim::PenModel::kPaperPush)
        return fail("--force is the paper push's (--pen paper)");
      s.pen_strength_m_per_s2 = args.force_m_per_s2.value;
    }
    if (!s.IsValid(&why)) return fail("water options: " + why);
  }
  const int n = args.cells == 0 ? DefaultWaterCells(*waves) : args.cells;
  if (n < 2 || n > 4096)
    return fail("--sim-cells " + std::to_string(args.cells) +
                ": must be in [2, 4096] (0: the model's default)");
  *options = o;
  *cells = n;
  return true;
}

bool WaterForRig(const tracking::Rig& rig, int cells, bool keep_radius,
                 sim::WaterModelOptions* options, sim::GridSpec* grid,
                 std::string* error) {
  if (rig.pen) {
    sim::SpectralWaterOptions& s = options->spectral;
    s.pen_shaft_radius_m = rig.pen->shaft_radius_m;
    s.pen_shaft_length_m = rig.pen->shaft_length_m;
    if (!keep_radius && rig.pen->shaft_radius_m > 0)
      s.pen_radius_m = rig.pen->shaft_radius_m;
  }
  if (options->waves == sim::WaveModel::kCapillaryGravity &&
      !(rig.tank.water_level_m > 0)) {
    if (error) *error = "rig: the capillary model needs a water level > 0";
    return false;
  }
  *grid = sim::DefaultGrid(options->waves, rig.tank.size_x_m, rig.tank.size_y_m,
                           rig.tank.water_level_m, cells);
  std::string why;
  if (!grid->IsValid(&why) || !options->IsValid(&why)) {
    if (error) *error = "water: " + why;
    return false;
  }
  return true;
}

}  // namespace ripple::app
