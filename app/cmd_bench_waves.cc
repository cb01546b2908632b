// `ripple bench waves`: phase speed and viscous decay of the
// capillary-gravity model per wavelength against the dispersion relation
// (bench/wave_bench.h); prints the table and writes bench_waves.csv.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>

#include "app/app_bench.h"
#include "app/app_common.h"
#include "bench/wave_bench.h"

namespace ripple::app {
namespace {

struct WavesArgs {
  std::string out = "bench_waves";
  bench::WaveBenchOptions options;
};

int RunBenchWaves(const WavesArgs& args) {
  std::string error;
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);
  std::vector<bench::WaveMeasurement> rows;
  if (!bench::RunWaveBench(args.options, &rows, &error))
    return Fail(kExitBadInput, error);
  const std::string path = args.out + "/bench_waves.csv";
  std::ofstream csv(path);
  if (!csv) return Fail(kExitBadInput, "cannot write '" + path + "'");
  csv << "wavelength_m,expected_speed_m_per_s,measured_speed_m_per_s,"
         "expected_decay_per_s,measured_decay_per_s\n";
  std::printf(
      "capillary-gravity waves, depth %.1f mm, nu %.2g m^2/s\n"
      "%8s %12s %12s %8s %12s %12s %8s\n",
      1e3 * args.options.depth_m, args.options.kinematic_viscosity_m2_per_s,
      "lambda_mm", "c_expected", "c_measured", "err_%", "decay_exp",
      "decay_meas", "err_%");
  for (const bench::WaveMeasurement& m : rows) {
    const double ec =
        100 * (m.measured_speed_m_per_s / m.expected_speed_m_per_s - 1);
    const double ed =
        m.expected_decay_per_s > 0
            ? 100 * (m.measured_decay_per_s / m.expected_decay_per_s - 1)
            : 0.0;
    std::printf("%8.1f %12.4f %12.4f %8.2f %12.4f %12.4f %8.2f\n",
                1e3 * m.wavelength_m, m.expected_speed_m_per_s,
                m.measured_speed_m_per_s, ec, m.expected_decay_per_s,
                m.measured_decay_per_s, ed);
    csv << m.wavelength_m << ',' << m.expected_speed_m_per_s << ','
        << m.measured_speed_m_per_s << ',' << m.expected_decay_per_s << ','
        << m.measured_decay_per_s << '\n';
  }
  csv.close();
  if (!csv) return Fail(kExitRuntime, "cannot write '" + path + "'");
  std::printf("wrote %s\n", path.c_str());
  return kExitOk;
}

CommandAction SetupBenchWaves(CLI::App* sub) {
  auto args = std::make_shared<WavesArgs>();
  sub->add_option("--out", args->out, "Output folder")->capture_default_str();
  sub->add_option("--wavelengths", args->options.wavelengths_m,
                  "Wavelengths, metres")
      ->check(CLI::Range(0.002, 1.0));
  sub->add_option("--depth", args->options.depth_m, "Water depth, metres")
      ->capture_default_str()
      ->check(CLI::Range(1e-4, 10.0));
  sub->add_option("--viscosity", args->options.kinematic_viscosity_m2_per_s,
                  "Kinematic viscosity nu, m^2/s")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1e-2));
  return [args] { return RunBenchWaves(*args); };
}

}  // namespace

RIPPLE_REGISTER_BENCH(waves,
                      "Phase speed and decay of the water's waves against "
                      "the capillary-gravity relation",
                      SetupBenchWaves);

}  // namespace ripple::app
