// Google Benchmark kernels for the capillary-gravity model: one 1/30 s frame
// at the default tank grid and at ~512 cells, with the pen stirring, with
// the pen and an obstacle, freely ringing, and at rest. Run (Release):
//   build/tests/sim/sim_spectral_benchmark --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true  (one command line)
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <string>

#include "sim/spectral_water.h"
#include "sim/water_factory.h"

namespace ripple::sim {
namespace {

constexpr double kFrame = 1.0 / 30.0;

std::unique_ptr<SpectralWater> MakeTank(int nx_min, bool pillar) {
  WaterModelOptions o;
  const GridSpec g = DefaultGrid(o.waves, 0.17, 0.11, 0.025, nx_min);
  std::string error;
  auto water = SpectralWater::Create(g, o, &error);
  if (pillar) {
    Obstacle p;
    p.shape = Obstacle::Shape::kCylinder;
    p.radius_m = 0.012;
    p.height_m = 0.05;
    p.tank_from_obstacle = RigidTransform::FromTranslation(0.045, 0.015, 0);
    water->AddObstacle(p, &error);
  }
  return water;
}

// The pen stirring in a circle at ~0.3 m/s, 10 mm deep.
void Stir(SpectralWater* water, int frame) {
  const double t = frame * kFrame;
  water->SetPenTip({0.03 * std::cos(10 * t), 0.03 * std::sin(10 * t), 0.015});
}

void BM_FrameStirring(benchmark::State& state) {
  auto water = MakeTank(static_cast<int>(state.range(0)), state.range(1) != 0);
  int frame = 0;
  for (int f = 0; f < 30; ++f) {
    Stir(water.get(), frame++);
    water->Advance(kFrame);
  }
  for (auto _ : state) {
    Stir(water.get(), frame++);
    water->Advance(kFrame);
    benchmark::DoNotOptimize(water->View().heights);
  }
  state.counters["cells"] = water->grid().nx * water->grid().ny;
}
BENCHMARK(BM_FrameStirring)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Args({512, 0})
    ->Args({512, 1})
    ->Unit(benchmark::kMillisecond);

// Waves ringing after the pen left: the propagation and one synthesis.
void BM_FrameRinging(benchmark::State& state) {
  auto water = MakeTank(static_cast<int>(state.range(0)), false);
  for (int f = 0; f < 30; ++f) {
    Stir(water.get(), f);
    water->Advance(kFrame);
  }
  water->ClearPen();
  for (auto _ : state) {
    water->Advance(kFrame);
    benchmark::DoNotOptimize(water->View().heights);
  }
}
BENCHMARK(BM_FrameRinging)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);

// At rest with the pen out of the water: must return at once, unchanged.
void BM_FrameAtRest(benchmark::State& state) {
  auto water = MakeTank(256, true);
  water->SetPenTip({0, 0, 0.05});
  water->Advance(kFrame);
  for (auto _ : state) {
    water->SetPenTip({0, 0, 0.05});
    water->Advance(kFrame);
    if (water->stats().changed) state.SkipWithError("changed at rest");
  }
}
BENCHMARK(BM_FrameAtRest)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ripple::sim
