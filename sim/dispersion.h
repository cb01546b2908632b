// Linear capillary-gravity waves on water of finite depth (Lamb, Hydrodynamics,
// sec. 267; Lighthill, Waves in Fluids, 3.2): a surface mode cos(k.x) of wave
// number k = |k| oscillates at
//   omega(k)^2 = (g*k + (sigma/rho)*k^3) * tanh(k*H)
// and, in a fluid of kinematic viscosity nu, its amplitude decays at the rate
//   gamma(k) = 2*nu*k^2                     (Lamb, sec. 348)
// which holds while gamma << omega (true for water at every k a tank grid
// resolves); for larger nu (honey) the mode is simply over-damped.
#ifndef RIPPLE_SIM_DISPERSION_H_
#define RIPPLE_SIM_DISPERSION_H_

#include <string>

namespace ripple::sim {

struct CapillaryGravity {
  double gravity_m_per_s2 = 9.81;
  // Surface tension over density sigma/rho, m^3/s^2 (clean water, 20 C).
  double tension_m3_per_s2 = 7.28e-5;
  double depth_m = 0.025;  // H, water depth at rest
  // nu, m^2/s: water 1.0e-6, olive oil ~1e-4, honey ~1e-3 to 1e-2.
  double kinematic_viscosity_m2_per_s = 1.0e-6;

  // Every value finite; g, sigma/rho >= 0, H > 0, nu >= 0.
  bool IsValid(std::string* error) const;

  // Angular frequency omega(k), rad/s, for a wave number k >= 0 in rad/m.
  double Omega(double k_per_m) const;
  // omega/k, m/s (the k -> 0 limit sqrt(g*H) at k = 0).
  double PhaseSpeed(double k_per_m) const;
  // d omega / dk, m/s (central difference of Omega, relative step 1e-5).
  double GroupSpeed(double k_per_m) const;
  // Amplitude decay rate 2*nu*k^2, 1/s.
  double DampingRate(double k_per_m) const;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_DISPERSION_H_
