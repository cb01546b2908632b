#include "sim/dispersion.h"

#include <cmath>

namespace ripple::sim {

bool CapillaryGravity::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = m;
    return false;
  };
  if (!std::isfinite(gravity_m_per_s2) || gravity_m_per_s2 < 0 ||
      gravity_m_per_s2 > 1e3)
    return fail("gravity must be in [0, 1000] m/s^2");
  if (!std::isfinite(tension_m3_per_s2) || tension_m3_per_s2 < 0 ||
      tension_m3_per_s2 > 1)
    return fail("surface tension / density must be in [0, 1] m^3/s^2");
  if (!std::isfinite(depth_m) || !(depth_m > 0) || depth_m > 1e3)
    return fail("water depth must be in (0, 1000] m");
  if (!std::isfinite(kinematic_viscosity_m2_per_s) ||
      kinematic_viscosity_m2_per_s < 0 || kinematic_viscosity_m2_per_s > 1)
    return fail("kinematic viscosity must be in [0, 1] m^2/s");
  return true;
}

double CapillaryGravity::Omega(double k) const {
  if (!(k > 0)) return 0;
  const double w2 = (gravity_m_per_s2 * k + tension_m3_per_s2 * k * k * k) *
                    std::tanh(k * depth_m);
  return std::sqrt(w2);
}

double CapillaryGravity::PhaseSpeed(double k) const {
  if (!(k > 0)) return std::sqrt(gravity_m_per_s2 * depth_m);
  return Omega(k) / k;
}

double CapillaryGravity::GroupSpeed(double k) const {
  const double dk = std::max(k, 1.0) * 1e-5;
  return (Omega(k + dk) - Omega(std::max(0.0, k - dk))) /
         (k + dk - std::max(0.0, k - dk));
}

double CapillaryGravity::DampingRate(double k) const {
  return 2.0 * kinematic_viscosity_m2_per_s * k * k;
}

}  // namespace ripple::sim
