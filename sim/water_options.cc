#include "sim/water_options.h"

#include <cmath>

namespace ripple::sim {

std::optional<WaveModel> ParseWaveModel(const std::string& name) {
  if (name == "capillary") return WaveModel::kCapillaryGravity;
  if (name == "paper") return WaveModel::kPaper;
  return std::nullopt;
}

std::optional<PenModel> ParsePenModel(const std::string& name) {
  if (name == "displace") return PenModel::kDisplace;
  if (name == "paper") return PenModel::kPaperPush;
  return std::nullopt;
}

const char* WaveModelName(WaveModel model) {
  return model == WaveModel::kPaper ? "paper" : "capillary";
}

const char* PenModelName(PenModel model) {
  return model == PenModel::kPaperPush ? "paper" : "displace";
}

bool SpectralWaterOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  auto in = [](double v, double lo, double hi) {
    return std::isfinite(v) && v >= lo && v <= hi;
  };
  if (!physics.IsValid(error)) return false;
  if (!in(substep_s, 1e-6, 0.1) || !(substep_s > 0))
    return fail("sub-step must be in [1e-6, 0.1] s");
  if (!in(shortest_wavelength_m, 1e-6, 10))
    return fail("shortest wavelength must be in [1e-6, 10] m");
  if (walls != WallMode::kReflect && walls != WallMode::kAbsorb)
    return fail("unknown wall mode");
  if (!in(sponge_width_m, 0, 10))
    return fail("sponge width must be in [0, 10] m");
  if (!in(sponge_rate_per_s, 0, 1e6))
    return fail("sponge rate must be in [0, 1e6] 1/s");
  if (!in(boundary_step_s, 1e-6, 1))
    return fail("boundary step must be in [1e-6, 1] s");
  if (pen != PenModel::kDisplace && pen != PenModel::kPaperPush)
    return fail("unknown pen model");
  if (!in(pen_shaft_radius_m, 0, 1))
    return fail("shaft radius must be in [0, 1] m");
  if (!in(pen_shaft_length_m, 0, 10))
    return fail("shaft length must be in [0, 10] m");
  if (!in(pen_radius_m, 1e-6, 1))
    return fail("pen radius must be in [1e-6, 1] m");
  if (!in(pen_strength_m_per_s2, 0, 1e12))
    return fail("pen strength must be in [0, 1e12] m/s^2");
  if (!in(pen_pressure_coefficient, 0, 100))
    return fail("pen pressure coefficient must be in [0, 100]");
  if (!in(pen_max_speed_m_per_s, 1e-6, 1e3))
    return fail("pen max speed must be in [1e-6, 1000] m/s");
  if (!in(pen_withdraw_speed_m_per_s, 1e-6, 1e3))
    return fail("pen withdraw speed must be in [1e-6, 1000] m/s");
  if (max_substeps < 1 || max_substeps > 1000000)
    return fail("max sub-steps must be in [1, 1000000]");
  if (!in(rest_speed_m_per_s, 0, 1e3) || !in(rest_height_m, 0, 1e3))
    return fail("rest thresholds must be >= 0");
  return true;
}

bool WaterModelOptions::IsValid(std::string* error) const {
  if (waves == WaveModel::kPaper) return paper.IsValid(error);
  if (waves == WaveModel::kCapillaryGravity) return spectral.IsValid(error);
  if (error) *error = "unknown wave model";
  return false;
}

}  // namespace ripple::sim
