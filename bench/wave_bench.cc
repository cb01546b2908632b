#include "bench/wave_bench.h"

#include <cmath>

#include "sim/spectral_water.h"

namespace ripple::bench {
namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

bool RunWaveBench(const WaveBenchOptions& options,
                  std::vector<WaveMeasurement>* out, std::string* error) {
  out->clear();
  sim::CapillaryGravity physics;
  physics.depth_m = options.depth_m;
  physics.kinematic_viscosity_m2_per_s = options.kinematic_viscosity_m2_per_s;
  if (!physics.IsValid(error)) return false;
  for (double lambda : options.wavelengths_m) {
    // A channel of whole half-wavelengths, at least 60 mm and 4 waves.
    const int halves =
        std::max(8, static_cast<int>(std::ceil(2 * 0.06 / lambda)));
    const double length = halves * lambda / 2;
    const int nx = static_cast<int>(std::lround(length / options.cell_m));
    sim::GridSpec grid;
    grid.nx = nx;
    grid.ny = 2;
    grid.cell_m = length / nx;
    grid.rest_level_m = options.depth_m;
    sim::WaterModelOptions o;
    o.spectral.physics = physics;
    o.spectral.substep_s = options.substep_s;
    o.spectral.shortest_wavelength_m = 2 * grid.cell_m;
    o.spectral.rest_speed_m_per_s = 0;
    o.spectral.rest_height_m = 0;
    auto water = sim::SpectralWater::Create(grid, o, error);
    if (!water) return false;
    std::vector<float> h(static_cast<std::size_t>(nx) * 2);
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < nx; ++i)
        h[static_cast<std::size_t>(j) * nx + i] =
            static_cast<float>(1e-4 * std::cos(kPi * halves * (i + 0.5) / nx));
    water->SetState(h, nullptr);
    water->Advance(0.0);
    const double energy0 = water->stats().energy;
    WaveMeasurement m;
    m.wavelength_m = lambda;
    const double k = 2 * kPi / lambda;
    m.expected_speed_m_per_s = physics.PhaseSpeed(k);
    m.expected_decay_per_s = physics.DampingRate(k);
    const double duration = options.periods * lambda / m.expected_speed_m_per_s;
    double prev = water->View().heights[0], t = 0, first = -1, last = -1;
    int crossings = 0;
    while (t < duration) {
      water->Advance(options.substep_s);
      t += options.substep_s;
      const double cur = water->View().heights[0];
      if ((prev > 0) != (cur > 0)) {
        const double tc = t - options.substep_s * cur / (cur - prev);
        if (first < 0) first = tc;
        last = tc;
        ++crossings;
      }
      prev = cur;
    }
    if (crossings >= 3)
      m.measured_speed_m_per_s = kPi * (crossings - 1) / (last - first) / k;
    // Energy ~ amplitude^2 falls as exp(-2 gamma t).
    if (energy0 > 0 && water->stats().energy > 0)
      m.measured_decay_per_s =
          -std::log(water->stats().energy / energy0) / (2 * t);
    out->push_back(m);
  }
  return true;
}

}  // namespace ripple::bench
