// Google Benchmark kernels for the water simulation. Inputs are built
// outside the timed loops; sizes are swept. Run (Release build):
//   build-sim/tests/sim/sim_sim_benchmark --benchmark_repetitions=5
//       --benchmark_report_aggregates_only=true  (one command line)
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "sim/water.h"

namespace ripple::sim {
namespace {

GridSpec Square(int n) {
  GridSpec g;
  g.nx = g.ny = n;
  g.cell_m = 0.17 / n;
  g.rest_level_m = 0.025;
  return g;
}

// A wavy state so that nothing is trivially zero.
template <typename T>
void Disturb(BasicWater<T>* water) {
  const GridSpec& g = water->grid();
  std::vector<T> h(static_cast<size_t>(g.nx) * g.ny);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      h[static_cast<size_t>(j) * g.nx + i] =
          T(1e-3 * std::sin(0.3 * i) * std::cos(0.2 * j));
  water->SetState(h);
}

// The bare sub-step (docs/sim.md's speed table), reflecting walls, no
// obstacles, float.
void BM_SubStep(benchmark::State& state) {
  Water water(Square(static_cast<int>(state.range(0))), WaterOptions());
  Disturb(&water);
  for (auto _ : state) {
    water.Step(1);
    benchmark::DoNotOptimize(water.heights());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}
BENCHMARK(BM_SubStep)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Arg(2048);

// Sub-step with a reflecting obstacle (masked kernel).
void BM_SubStepObstacle(benchmark::State& state) {
  WaterOptions options;
  options.obstacles =
      state.range(1) ? ObstacleMode::kReflect : ObstacleMode::kZero;
  Water water(Square(static_cast<int>(state.range(0))), options);
  Obstacle pillar;
  pillar.shape = Obstacle::Shape::kCylinder;
  pillar.radius_m = 0.02;
  pillar.height_m = 0.05;
  water.AddObstacle(pillar, nullptr);
  Disturb(&water);
  for (auto _ : state) {
    water.Step(1);
    benchmark::DoNotOptimize(water.heights());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0) * state.range(0));
}
BENCHMARK(BM_SubStepObstacle)
    ->Args({256, 0})
    ->Args({256, 1})
    ->Args({1024, 0})
    ->Args({1024, 1});

// Absorbing walls (Mur ghosts around the kernel).
void BM_SubStepAbsorbing(benchmark::State& state) {
  WaterOptions options;
  options.walls = WallMode::kAbsorb;
  Water water(Square(static_cast<int>(state.range(0))), options);
  Disturb(&water);
  for (auto _ : state) {
    water.Step(1);
    benchmark::DoNotOptimize(water.heights());
  }
}
BENCHMARK(BM_SubStepAbsorbing)->Arg(256)->Arg(1024);

// Double-precision kernel (used by the exact-invariant tests).
void BM_SubStepDouble(benchmark::State& state) {
  WaterD water(Square(static_cast<int>(state.range(0))), WaterOptions());
  Disturb(&water);
  for (auto _ : state) {
    water.Step(1);
    benchmark::DoNotOptimize(water.heights());
  }
}
BENCHMARK(BM_SubStepDouble)->Arg(256)->Arg(1024);

// Advance() at rest with the pen above the water: must be ~free.
void BM_AdvanceAtRest(benchmark::State& state) {
  Water water(Square(static_cast<int>(state.range(0))), WaterOptions());
  water.SetPenTip({0.0, 0.0, 0.1});
  water.Advance(1.0 / 60);
  for (auto _ : state) {
    water.Advance(1.0 / 60);
    benchmark::DoNotOptimize(water.stats());
  }
}
BENCHMARK(BM_AdvanceAtRest)->Arg(128)->Arg(1024);

// One 60 Hz frame with the pen stirring (sub-steps + pen + statistics).
void BM_AdvanceFrame(benchmark::State& state) {
  Water water(Square(static_cast<int>(state.range(0))), WaterOptions());
  double t = 0;
  for (auto _ : state) {
    t += 1.0 / 60;
    water.SetPenTip({0.05 * std::cos(3 * t), 0.03 * std::sin(3 * t), 0.02});
    water.Advance(1.0 / 60);
    benchmark::DoNotOptimize(water.stats());
  }
  state.counters["substeps"] = water.stats().substeps;
}
BENCHMARK(BM_AdvanceFrame)->Arg(128)->Arg(256)->Unit(benchmark::kMicrosecond);

// The statistics pass alone (once per Advance).
void BM_Gradients(benchmark::State& state) {
  Water water(Square(static_cast<int>(state.range(0))), WaterOptions());
  Disturb(&water);
  std::vector<float> gx, gy;
  for (auto _ : state) {
    ComputeGradients(water.View(), &gx, &gy);
    benchmark::DoNotOptimize(gx.data());
  }
}
BENCHMARK(BM_Gradients)->Arg(256);

}  // namespace
}  // namespace ripple::sim
