// The capillary-gravity model measured against the relation it claims: a
// standing wave of each wavelength in a 1-D channel (reflecting ends), its
// phase speed from the synthesised surface's zero crossings and its decay
// from the modal energy, beside omega(k)/k and 2 nu k^2.
#ifndef RIPPLE_BENCH_WAVE_BENCH_H_
#define RIPPLE_BENCH_WAVE_BENCH_H_

#include <string>
#include <vector>

#include "sim/dispersion.h"

namespace ripple::bench {

struct WaveBenchOptions {
  std::vector<double> wavelengths_m = {0.004, 0.005, 0.008, 0.0171,
                                       0.03,  0.05,  0.08};
  double depth_m = 0.025;
  double kinematic_viscosity_m2_per_s = 1.0e-6;
  double cell_m = 0.0005;   // channel cells
  double substep_s = 1e-4;  // sampling of the zero crossings
  int periods = 12;         // measured per wavelength
};

struct WaveMeasurement {
  double wavelength_m = 0;
  double expected_speed_m_per_s = 0;  // omega(k)/k
  double measured_speed_m_per_s = 0;
  double expected_decay_per_s = 0;  // 2 nu k^2 (amplitude)
  double measured_decay_per_s = 0;
};

// One measurement per wavelength; false with `error` on bad options.
bool RunWaveBench(const WaveBenchOptions& options,
                  std::vector<WaveMeasurement>* out, std::string* error);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_WAVE_BENCH_H_
