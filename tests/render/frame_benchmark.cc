// Whole-frame cost on the GL backends (EGL/llvmpipe headless by default):
// 640x480 output, a 128x128 simulation over a 17 cm square tank. Each
// iteration renders and waits for the GPU (glFinish); readback is measured
// separately. LP_NUM_THREADS=2 reproduces the
// target machine's 2 cores.
//
//   build/tests/render/render_frame_benchmark
//
// BM_MainPassWithout splits mode 0 into its parts; for comparable numbers
// interleave the runs: --benchmark_enable_random_interleaving=true.
#include <benchmark/benchmark.h>
#include <time.h>
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define RIPPLE_HAVE_CALLGRIND 1
#endif

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "render/renderer.h"
#include "tests/render/render_test_util.h"

namespace ripple::render {
namespace {

constexpr int kW = 640, kH = 480, kN = 128;

// The machine is shared: report the least-disturbed repetition too.
double MinOf(const std::vector<double>& v) {
  return *std::min_element(v.begin(), v.end());
}

// Instruction counts that other load cannot disturb: under
//   LP_NUM_THREADS=0 valgrind --tool=callgrind --collect-atstart=no
//       --smc-check=all-non-file render_frame_benchmark --benchmark_filter=...
// callgrind counts only the timed frames (shader compilation and the first
// frame's set-up excluded); with LP_NUM_THREADS=0 llvmpipe rasterises on the
// calling thread, so the count is all the frame's work. Divide by the
// iterations the benchmark prints. A no-op outside valgrind.
class CallgrindRegion {
 public:
  CallgrindRegion() {
#ifdef RIPPLE_HAVE_CALLGRIND
    CALLGRIND_TOGGLE_COLLECT;
#endif
  }
  ~CallgrindRegion() {
#ifdef RIPPLE_HAVE_CALLGRIND
    CALLGRIND_TOGGLE_COLLECT;
#endif
  }
  CallgrindRegion(const CallgrindRegion&) = delete;
  CallgrindRegion& operator=(const CallgrindRegion&) = delete;
};

// CPU time of the whole process (all threads: the caller and llvmpipe's
// rasterizer threads), milliseconds. Less disturbed by other load on a
// shared machine than wall time, and what two cores have to give.
double ProcessCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

struct Fixture {
  std::unique_ptr<Context> ctx;
  std::unique_ptr<Renderer> renderer;
  testing::TestScene scene;
  std::vector<float> heights;
};

std::unique_ptr<Fixture> Make(benchmark::State& state, Backend backend,
                              bool distorted = false,
                              const RendererOptions& options = {},
                              int width = kW, int height = kH) {
  auto f = std::make_unique<Fixture>();
  std::string error;
  f->ctx = Context::TryCreate(backend, width, height, &error, false);
  if (f->ctx == nullptr) {
    state.SkipWithError(("no GL context: " + error).c_str());
    return nullptr;
  }
  f->scene = testing::MakeScene(width, height, testing::View::kFront, true);
  // A typical webcam lens (the shipped default calibration has none): the
  // video is then undistorted by a shader pass instead of copied.
  if (distorted) f->scene.k.dist = {-0.12, 0.08, 0.0005, -0.0003, -0.02};
  f->scene.inputs.tank.size_y = f->scene.inputs.tank.size_x;
  const float d = f->scene.inputs.tank.size_x / kN;
  f->heights.assign(kN * kN, 0.0f);
  for (int j = 0; j < kN; ++j) {
    for (int i = 0; i < kN; ++i) {
      const double x = (i - 0.5 * kN) * d, y = (j - 0.5 * kN) * d;
      const double r = std::hypot(x - 0.02, y);
      f->heights[j * kN + i] = static_cast<float>(0.0015 * std::cos(r / 0.002) *
                                                  std::exp(-r * r / 0.0004));
    }
  }
  f->scene.inputs.water = {f->heights.data(), kN, kN, d, 1};
  f->scene.inputs.pen_visible = true;
  // Pen upright (its +z is away from the tip), tip 5 mm under the surface.
  f->scene.inputs.tank_from_pen[3] = glm::dvec4(0.03, 0.0, 0.16, 1.0);
  Obstacle pillar;
  pillar.tank_from_obstacle[3] = glm::dvec4(0.045, 0.015, 0.0, 1.0);
  f->scene.inputs.obstacles.push_back(pillar);
  f->renderer = Renderer::TryCreate(f->ctx.get(), f->scene.k, options, &error);
  if (f->renderer == nullptr) {
    state.SkipWithError(error.c_str());
    return nullptr;
  }
  state.SetLabel(f->ctx->Description());
  return f;
}

// What changes between frames.
enum Mode : int {
  kMainOnly = 0,   // shadow and caustics off, water changes
  kFullChanging,   // all passes, water and pen change every frame
  kFullIdle,       // water at rest, pen still: shadow/caustics skipped
  kMainDistorted,  // kMainOnly through a lens with distortion
  // kMainOnly with the video alternating between two frames (the second
  // 24 levels brighter): with the cube map, it is rebuilt every frame.
  kMainVideoChanging,
};

void BM_Frame(benchmark::State& state) {
  const Mode mode = static_cast<Mode>(state.range(0));
  const Backend backend = static_cast<Backend>(state.range(1));
  RendererOptions options;
  options.reflection_map = static_cast<ReflectionMap>(state.range(2));
  auto f = Make(state, backend, mode == kMainDistorted, options);
  if (!f) return;
  SceneInputs& in = f->scene.inputs;
  in.effects.shadows = in.effects.caustics =
      mode == kFullChanging || mode == kFullIdle;
  std::vector<std::uint8_t> brighter = f->scene.video;
  for (std::uint8_t& v : brighter)
    v = static_cast<std::uint8_t>(std::min(255, v + 24));
  const std::uint8_t* videos[2] = {f->scene.video.data(), brighter.data()};
  f->renderer->Render(in);
  f->renderer->Finish();
  double shadow = 0, caustics = 0, frames = 0, rebuilds = 0;
  const double cpu0 = ProcessCpuMs();
  const CallgrindRegion counted;
  for (auto _ : state) {
    if (mode != kFullIdle) {
      in.water.change_counter++;
      in.tank_from_pen[3].x += (int(frames) % 2 ? -0.002 : 0.002);
    }
    if (mode == kMainVideoChanging) in.video.bgr = videos[int(frames) % 2];
    f->renderer->Render(in);
    f->renderer->Finish();
    shadow += f->renderer->timings().shadow_redrawn;
    caustics += f->renderer->timings().caustics_ms;
    rebuilds += f->renderer->timings().envmap_rebuilt;
    ++frames;
  }
  state.counters["process_cpu_ms"] = (ProcessCpuMs() - cpu0) / frames;
  state.counters["shadow_redraws_per_frame"] = shadow / frames;
  state.counters["caustics_cpu_ms"] = caustics / frames;
  state.counters["envmap_rebuilds_per_frame"] = rebuilds / frames;
}
// reflection: 0 the fold, 1 the cube map (ReflectionMap).
BENCHMARK(BM_Frame)
    ->ArgNames({"mode", "backend", "reflection"})
    ->Args({kMainOnly, int(Backend::kEgl), 0})
    ->Args({kMainOnly, int(Backend::kEgl), 1})
    ->Args({kFullChanging, int(Backend::kEgl), 0})
    ->Args({kFullChanging, int(Backend::kEgl), 1})
    ->Args({kFullIdle, int(Backend::kEgl), 0})
    ->Args({kFullIdle, int(Backend::kEgl), 1})
    ->Args({kMainDistorted, int(Backend::kEgl), 0})
    ->Args({kMainVideoChanging, int(Backend::kEgl), 0})
    ->Args({kMainVideoChanging, int(Backend::kEgl), 1})
    ->Args({kMainOnly, int(Backend::kOsmesa), 0})
    ->Args({kFullChanging, int(Backend::kOsmesa), 0})
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// What each part of the main pass (mode 0, EGL) costs: the same frame with
// one part taken away (the tank's shadow, off by default, added).
enum Without : int {
  kNothing = 0,
  kReflection,
  kRefraction,
  kWalls,
  kPenOcclusion,
  kObstacles,
  kVideoUpload,      // the video is uploaded once, not every frame
  kWaterShading,     // flat-colour water (mesh and stencil still drawn)
  kRealObjects,      // no submerged pen or plate lookups in the water
  kTankShadow,       // not taken away but added: the tank's shadow (off by
                     // default) on the board around the tank
  kCubicRefraction,  // the refracted video by one bilinear fetch, not the
                     // default Catmull-Rom lookup (RefractionFilter)
};
void BM_MainPassWithout(benchmark::State& state) {
  const Without without = static_cast<Without>(state.range(0));
  RendererOptions options;
  if (without == kCubicRefraction)
    options.refraction_filter = RefractionFilter::kLinear;
  auto f = Make(state, Backend::kEgl, false, options);
  if (!f) return;
  SceneInputs& in = f->scene.inputs;
  in.effects.shadows = in.effects.caustics = false;
  in.effects.reflection = without != kReflection;
  in.effects.refraction = without != kRefraction;
  in.effects.walls = without != kWalls;
  in.effects.pen_occludes = without != kPenOcclusion;
  in.effects.flat_water = without == kWaterShading;
  in.effects.real_objects = without != kRealObjects;
  in.effects.tank_shadow = without == kTankShadow;
  if (without == kObstacles) in.obstacles.clear();
  f->renderer->Render(in);
  f->renderer->Finish();
  if (without == kVideoUpload) in.video.bgr = nullptr;
  double upload_ms = 0, frames = 0;
  const double cpu0 = ProcessCpuMs();
  const CallgrindRegion counted;
  for (auto _ : state) {
    in.water.change_counter++;
    f->renderer->Render(in);
    f->renderer->Finish();
    upload_ms += f->renderer->timings().upload_ms;
    ++frames;
  }
  state.counters["process_cpu_ms"] = (ProcessCpuMs() - cpu0) / frames;
  state.counters["upload_ms"] = upload_ms / frames;
}
BENCHMARK(BM_MainPassWithout)
    ->ArgNames({"without"})
    ->DenseRange(kNothing, kCubicRefraction)
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// Each shadow filter (RendererOptions::shadow_filter): the pillar moves a
// millimetre every frame, so the shadow pass redraws each time; the
// counters split the frame into the shadow pass (depth map and receiver
// map, whose texels run the filter four times each) and the main pass (the
// obstacle's own pixels run it once; the water and walls read the receiver
// map), both wall times with glFinish.
void BM_ShadowFilter(benchmark::State& state) {
  RendererOptions options;
  options.shadow_filter = static_cast<ShadowFilter>(state.range(0));
  options.timing = RendererOptions::Timing::kCpuFinish;
  auto f = Make(state, Backend::kEgl, false, options);
  if (!f) return;
  SceneInputs& in = f->scene.inputs;
  in.effects.caustics = false;
  f->renderer->Render(in);
  f->renderer->Finish();
  double shadow_ms = 0, main_ms = 0, frames = 0;
  for (auto _ : state) {
    in.water.change_counter++;
    in.obstacles[0].tank_from_obstacle[3].x +=
        (int(frames) % 2 ? -0.002 : 0.002);
    f->renderer->Render(in);
    f->renderer->Finish();
    shadow_ms += f->renderer->timings().shadow_ms;
    main_ms += f->renderer->timings().main_ms;
    ++frames;
  }
  state.counters["shadow_ms"] = shadow_ms / frames;
  state.counters["main_ms"] = main_ms / frames;
  state.SetLabel(ShadowFilterName(options.shadow_filter));
}
BENCHMARK(BM_ShadowFilter)
    ->ArgNames({"filter"})
    ->Arg(int(ShadowFilter::kPcf))
    ->Arg(int(ShadowFilter::kGauss))
    ->Arg(int(ShadowFilter::kHard))
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// The water regions (RendererOptions::water_regions) on the main pass (as
// mode 0): the benchmark's ring (slopes up to 0.75, the regions' bounds
// widen with the steepest slope) and the same ring at a fifth of its height
// (slopes up to 0.15, as the demo's strokes), each with the regions on and
// off.
void BM_WaterRegions(benchmark::State& state) {
  const bool calm = state.range(0) != 0;
  RendererOptions options;
  options.water_regions = state.range(1) != 0;
  auto f = Make(state, Backend::kEgl, false, options);
  if (!f) return;
  if (calm)
    for (float& h : f->heights) h *= 0.2f;
  SceneInputs& in = f->scene.inputs;
  in.effects.shadows = in.effects.caustics = false;
  f->renderer->Render(in);
  f->renderer->Finish();
  const CallgrindRegion counted;
  for (auto _ : state) {
    in.water.change_counter++;
    f->renderer->Render(in);
    f->renderer->Finish();
  }
}
BENCHMARK(BM_WaterRegions)
    ->ArgNames({"calm", "regions"})
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

// A webcam's modes: the whole frame as the pipeline runs it (render, wait,
// read back into a BGR image) at each size, with the same field of view,
// the water shaded on `cols` columns (RendererOptions::
// water_shading_columns; -1: automatic, 0: at the output's pixels). Effects as
// in kFullChanging (water and pen change every frame), the tank's shadow on
// the board around it as `tank_shadow` says.
void BM_FrameAtSize(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0));
  const int h = static_cast<int>(state.range(1));
  RendererOptions options;
  options.water_shading_columns = static_cast<int>(state.range(2));
  auto f = Make(state, Backend::kEgl, false, options, w, h);
  if (!f) return;
  SceneInputs& in = f->scene.inputs;
  in.effects.tank_shadow = state.range(3) != 0;
  std::vector<std::uint8_t> out(static_cast<size_t>(w) * h * 3);
  f->renderer->Render(in);
  f->renderer->ReadBgr(out.data());
  double frames = 0, upload_ms = 0, render_cpu = 0, read_cpu = 0;
  const double cpu0 = ProcessCpuMs();
  const CallgrindRegion counted;
  for (auto _ : state) {
    in.water.change_counter++;
    in.tank_from_pen[3].x += (int(frames) % 2 ? -0.002 : 0.002);
    const double c0 = ProcessCpuMs();
    f->renderer->Render(in);
    f->renderer->Finish();
    const double c1 = ProcessCpuMs();
    f->renderer->ReadBgr(out.data());
    benchmark::DoNotOptimize(out.data());
    read_cpu += ProcessCpuMs() - c1;
    render_cpu += c1 - c0;
    upload_ms += f->renderer->timings().upload_ms;
    ++frames;
  }
  state.counters["process_cpu_ms"] = (ProcessCpuMs() - cpu0) / frames;
  state.counters["render_cpu_ms"] = render_cpu / frames;
  state.counters["read_cpu_ms"] = read_cpu / frames;
  state.counters["upload_ms"] = upload_ms / frames;
}
BENCHMARK(BM_FrameAtSize)
    ->ArgNames({"w", "h", "cols", "tank_shadow"})
    ->Args({640, 480, kWaterColumnsAuto, 0})
    ->Args({640, 480, kWaterColumnsAuto, 1})
    ->Args({640, 480, 0, 0})
    ->Args({1280, 720, kWaterColumnsAuto, 0})
    ->Args({1280, 720, kWaterColumnsAuto, 1})
    ->Args({1280, 720, 0, 0})
    ->Args({1920, 1080, kWaterColumnsAuto, 0})
    ->Args({1920, 1080, 0, 0})
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

void BM_ReadBgr(benchmark::State& state) {
  auto f = Make(state, static_cast<Backend>(state.range(0)));
  if (!f) return;
  std::vector<std::uint8_t> out(kW * kH * 3);
  f->renderer->Render(f->scene.inputs);
  for (auto _ : state) {
    f->renderer->ReadBgr(out.data());
    benchmark::DoNotOptimize(out.data());
  }
}
BENCHMARK(BM_ReadBgr)
    ->ArgNames({"backend"})
    ->Arg(int(Backend::kEgl))
    ->Arg(int(Backend::kOsmesa))
    ->Unit(benchmark::kMillisecond)
    ->ComputeStatistics("min", MinOf)
    ->UseRealTime();

}  // namespace
}  // namespace ripple::render
