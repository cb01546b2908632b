// The reference renderer end to end on the ring-wave scene (640x480, 16
// samples per pixel unless the arguments say otherwise): the wet render
// through the ideal pinhole and the dry one through a distorting lens, as
// the benchmark that compares the real-time renderer will render them; and
// the light tracing alone per caustic-map size. `light` 0 is the project's
// default light, 1 the backlit one (glints in view). Counters: the light
// and camera passes' seconds.
//
//   build/tests/render/render_reference_benchmark
// With RIPPLE_REFERENCE_PNG_DIR=<folder> in the environment, BM_RingScene
// writes its last render there, sRGB: the wet one as reference_ring.png,
// the dry one as reference_ring_dry.png (docs/reference_ring.png is
// `--benchmark_filter='BM_RingScene/dry:0/spp:16/threads:2/ambient:4/light:1'`).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "tests/render/reference_test_util.h"

namespace ripple::reference {
namespace {

void BM_RingScene(benchmark::State& state) {
  const bool dry = state.range(0) != 0;
  auto owned = testing::MakeRingScene(640, 480, state.range(4) != 0);
  ReferenceScene& rs = owned->scene;
  if (dry) rs.camera.dist = {-0.12, 0.08, 0, 0, 0, 0, 0, 0};
  ReferenceOptions o;
  o.samples_per_pixel = static_cast<int>(state.range(1));
  o.threads = static_cast<int>(state.range(2));
  o.ambient_samples = static_cast<int>(state.range(3));
  o.dry = dry;
  o.distort = dry;
  cv::Mat img;
  ReferenceSummary summary;
  for (auto _ : state) {
    std::string error;
    if (!RenderReference(o, rs, &img, &summary, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
  }
  state.counters["light_s"] = summary.light_seconds;
  state.counters["camera_s"] = summary.camera_seconds;
  state.counters["paths"] = static_cast<double>(summary.light.paths);
  if (const char* dir = std::getenv("RIPPLE_REFERENCE_PNG_DIR")) {
    const std::string name =
        dry ? "/reference_ring_dry.png" : "/reference_ring.png";
    cv::imwrite(dir + name, LinearToSrgb8(img));
  }
}
BENCHMARK(BM_RingScene)
    ->ArgNames({"dry", "spp", "threads", "ambient", "light"})
    ->Args({0, 16, 2, 1, 0})
    ->Args({0, 16, 2, 4, 0})
    ->Args({1, 16, 2, 1, 0})
    ->Args({0, 16, 2, 4, 1})
    ->Args({1, 16, 2, 1, 1})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

void BM_LightMaps(benchmark::State& state) {
  auto owned = testing::MakeRingScene(640, 480);
  ReferenceOptions o;
  o.caustic_map_size = static_cast<int>(state.range(0));
  o.threads = static_cast<int>(state.range(1));
  LightTraceSummary summary;
  for (auto _ : state) {
    std::string error;
    if (!ComputeLightMaps(o, owned->scene, nullptr, &summary, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
  }
  state.counters["paths"] = static_cast<double>(summary.paths);
}
BENCHMARK(BM_LightMaps)
    ->ArgNames({"map", "threads"})
    ->Args({128, 2})
    ->Args({256, 1})
    ->Args({256, 2})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace ripple::reference
