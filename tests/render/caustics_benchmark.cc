// The CPU caustics kernel: an N x N surface into a 256 x 256 map, one core
// (threads = 1) unless the second argument says otherwise; the third
// turns on the light's 2-degree disc (the penumbra's convolution). The
// target is N = 128 in <= 1 ms on one core. And the glass walls' maps, once
// per tank and light.
//
//   build-render/tests/render/render_caustics_benchmark
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "render/caustics.h"

namespace ripple::render {
namespace {

double MinOf(const std::vector<double>& v) {
  return *std::min_element(v.begin(), v.end());
}

void BM_Caustics(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  TankGeometry tank;
  tank.size_y = tank.size_x;  // a square N x N field over the tank
  const float d = tank.size_x / n;
  std::vector<float> h(n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const double x = (i - 0.5 * n) * d - 0.02, y = (j - 0.5 * n) * d;
      const double r = std::hypot(x, y);
      h[j * n + i] = static_cast<float>(0.0015 * std::cos(r / 0.002) *
                                        std::exp(-r * r / 0.0016));
    }
  }
  const HeightFieldView view{h.data(), n, n, d, 1};
  CausticsOptions o;
  o.threads = static_cast<int>(state.range(1));
  // The renderer's default light: a disc of 2 degrees (its penumbra).
  if (state.range(2)) o.light_angular_radius_rad = 2.0 * M_PI / 180.0;
  o.attenuation_per_m = 5.0;
  std::vector<float> map;
  CausticsWorkspace workspace;
  for (auto _ : state) {
    ComputeCaustics(o, view, tank, {0.35, 0.25, 1.0}, &map, nullptr,
                    &workspace);
    benchmark::DoNotOptimize(map.data());
  }
  state.counters["triangles"] = 2.0 * n * n;
}
BENCHMARK(BM_Caustics)
    ->ArgNames({"n", "threads", "disc"})
    ->Args({64, 1, 0})
    ->Args({83, 1, 0})
    ->Args({128, 1, 0})
    ->Args({128, 1, 1})
    ->Args({256, 1, 0})
    ->Args({256, 1, 1})
    ->Args({128, 2, 0})
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// The glass walls' maps for flat water (CausticsOptions::glass_near_walls
// and light_through_walls), computed afresh: what a change of the light or
// the tank costs once, before the workspace caches them. The argument is
// the traced paths per texel and axis; the second, the light: 0 the
// renderer's default (0.35, 0.25, 1), 1 a low sun 10 degrees up.
void BM_CausticsWallMaps(benchmark::State& state) {
  CausticsOptions o;
  o.glass_paths_per_axis = static_cast<int>(state.range(0));
  const glm::dvec3 light = state.range(1) ? glm::dvec3(0.95, 0.3, 0.176)
                                          : glm::dvec3(0.35, 0.25, 1.0);
  std::vector<float> map;
  for (auto _ : state) {
    ComputeCaustics(o, HeightFieldView{}, TankGeometry{}, light, &map, nullptr);
    benchmark::DoNotOptimize(map.data());
  }
}
BENCHMARK(BM_CausticsWallMaps)
    ->ArgNames({"paths", "low_sun"})
    ->Args({2, 0})
    ->Args({4, 0})
    ->Args({8, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

}  // namespace
}  // namespace ripple::render
