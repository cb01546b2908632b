// Where the tracker's time goes, on frames of synth's benchmark preset at
// 640x480 (one thread): full-frame detection with and without Ripple's edge
// fit, bare libapriltag, and the whole tracker with and without region
// search; on the plain floor, and on the tiled floor (`floor:1`), whose grout
// grid the detector segments and rejects. `ripple bench tracking` measures time
// against error over 500+ frames; this benchmark splits the time into its
// parts.
//
//   build/tests/tracking/tracking_tracking_benchmark
//   --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <apriltag.h>
#include <benchmark/benchmark.h>
#include <common/image_u8.h>
#include <common/timeprofile.h>
#include <common/zarray.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "geometry/check.h"
#include "tracking/shaft_refine.h"
#include "tracking/synth/synth.h"
#include "tracking/tag_family.h"
#include "tracking/tracker.h"

namespace ripple::tracking {
namespace {

struct Frames {
  Camera camera;
  Rig rig;
  std::vector<cv::Mat> gray;
  std::vector<double> time_s;
  std::vector<std::optional<Pose>> cam_from_pen;  // the truth, if in view
};

// 100 frames: two 50-frame segments (smooth motion, one cut), on the plain
// floor or on the tiled one.
const Frames& BenchmarkFrames(bool tiles = false) {
  static const Frames* plain_frames = nullptr;
  static const Frames* tiled_frames = nullptr;
  const Frames*& frames = tiles ? tiled_frames : plain_frames;
  if (frames) return *frames;
  frames = [tiles] {
    auto* f = new Frames;
    std::string error;
    auto camera = LoadCamera(
        std::string(RIPPLE_SOURCE_DIR) + "/data/camera/default_640x480.yml",
        &error);
    RIPPLE_CHECK(camera.has_value(), error);
    f->camera = *camera;
    auto rig = LoadRig(std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml",
                       &error);
    RIPPLE_CHECK(rig.has_value(), error);
    f->rig = *rig;
    synth::SequenceOptions seq;
    seq.frames = 100;
    std::vector<synth::FrameSpec> specs;
    RIPPLE_CHECK(synth::MakeSequence(f->camera, f->rig, seq, &specs, &error),
                 error);
    synth::FloorOptions floor_options;
    floor_options.kind =
        tiles ? synth::FloorKind::kTiles : synth::FloorKind::kPlain;
    auto floor =
        synth::FloorPattern::Create(floor_options, f->rig.tank, &error);
    RIPPLE_CHECK(floor.has_value(), error);
    synth::SceneRenderer renderer(f->camera, f->rig, *floor);
    for (const synth::FrameSpec& spec : specs) {
      const synth::RenderedFrame frame =
          renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
      cv::Mat gray;
      cv::cvtColor(frame.image, gray, cv::COLOR_BGR2GRAY);
      f->gray.push_back(gray);
      f->time_s.push_back(spec.time_s);
      f->cam_from_pen.push_back(
          spec.scene.tank_from_pen
              ? std::optional<Pose>(spec.scene.cam_from_tank *
                                    *spec.scene.tank_from_pen)
              : std::nullopt);
    }
    return f;
  }();
  return *frames;
}

void BM_DetectFullFrame(benchmark::State& state) {
  const Frames& f = BenchmarkFrames(state.range(1) != 0);
  TagDetectorOptions options;
  options.family = f.rig.family;
  // edge_fit: 0 none, 1 each profile's own dark end, 2 the border's own
  // black (the default).
  options.edge_fit = state.range(0) != 0;
  options.edge_fit_border_black = state.range(0) == 2;
  TagDetector detector(options);
  size_t i = 0, tags = 0;
  for (auto _ : state) {
    tags += detector.Detect(f.gray[i % f.gray.size()]).size();
    ++i;
  }
  state.counters["tags/frame"] = double(tags) / i;
}
BENCHMARK(BM_DetectFullFrame)
    ->ArgNames({"edge_fit", "floor"})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond);

// The whole frame (tiled floor, default options) at decimation range(0):
// 2, the detector's at 640x480, against 1, the finer search for an object
// not yet acquired (RoiSearchOptions::acquire_finer).
void BM_DetectFullFrameAt(benchmark::State& state) {
  const Frames& f = BenchmarkFrames(true);
  TagDetectorOptions options;
  options.family = f.rig.family;
  TagDetector detector(options);
  const double decimate = static_cast<double>(state.range(0));
  size_t i = 0, tags = 0;
  for (auto _ : state) {
    tags += detector.Detect(f.gray[i % f.gray.size()], {}, decimate).size();
    ++i;
  }
  state.counters["tags/frame"] = double(tags) / i;
}
BENCHMARK(BM_DetectFullFrameAt)
    ->ArgNames({"decimate"})
    ->Arg(2)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

// The shaft's edge search at the true pose (ShaftEdgeSupport), what the
// tracker spends per branch on a frame where an ambiguous pen's two
// branches are both alive (TrackerOptions::pen_shaft_resolve_ratio).
void BM_ShaftEdgeSupport(benchmark::State& state) {
  const Frames& f = BenchmarkFrames(true);
  const ShaftRefineOptions options;
  size_t i = 0;
  double edges = 0, calls = 0;
  for (auto _ : state) {
    const size_t k = i++ % f.gray.size();
    if (!f.cam_from_pen[k]) continue;
    edges += ShaftEdgeSupport(f.gray[k], f.camera, *f.rig.pen, options,
                              *f.cam_from_pen[k]);
    ++calls;
  }
  state.counters["edges/side"] = calls > 0 ? edges / calls : 0;
  state.counters["pen_share"] = calls / std::max<double>(i, 1);
}
BENCHMARK(BM_ShaftEdgeSupport)->Unit(benchmark::kMicrosecond);

// libapriltag alone on the whole frame, decimate 2, refine_edges on, with
// min_white_black_diff = range(0) and quad_sigma = range(1) / 10, on the
// tiled floor when range(2).
void BM_LibapriltagFullFrame(benchmark::State& state) {
  const Frames& f = BenchmarkFrames(state.range(2) != 0);
  auto family = TagFamily::Create(f.rig.family);
  apriltag_detector_t* td = apriltag_detector_create();
  apriltag_detector_add_family_bits(td, family->get(), 1);
  td->quad_decimate = 2.0f;
  td->nthreads = 1;
  td->qtp.min_white_black_diff = state.range(0);
  td->quad_sigma = state.range(1) / 10.0f;
  size_t i = 0;
  double segments = 0, quads = 0, tags = 0;
  for (auto _ : state) {
    const cv::Mat& g = f.gray[i++ % f.gray.size()];
    image_u8_t im{g.cols, g.rows, static_cast<int32_t>(g.step[0]),
                  const_cast<uint8_t*>(g.ptr<uint8_t>())};
    zarray_t* found = apriltag_detector_detect(td, &im);
    tags += zarray_size(found);
    segments += td->nsegments;
    quads += td->nquads;
    apriltag_detections_destroy(found);
  }
  if (std::getenv("RIPPLE_APRILTAG_PROFILE")) timeprofile_display(td->tp);
  state.counters["segments"] = segments / i;
  state.counters["quads"] = quads / i;
  state.counters["tags"] = tags / i;
  apriltag_detector_destroy(td);
}
BENCHMARK(BM_LibapriltagFullFrame)
    ->ArgNames({"min_wb_diff", "sigma_x10", "floor"})
    ->Args({5, 0, 0})
    ->Args({20, 0, 0})
    ->Args({40, 0, 0})
    ->Args({5, 8, 0})
    ->Args({20, 8, 0})
    ->Args({5, 0, 1})
    ->Unit(benchmark::kMillisecond);

// The whole tracker over the sequence (detection, pose, temporal logic).
void BM_Track(benchmark::State& state) {
  const Frames& f = BenchmarkFrames(state.range(2) != 0);
  TrackerOptions options;
  options.roi.enabled = state.range(0) != 0;
  options.pen_dense.enabled = state.range(1) != 0;
  Tracker tracker(f.camera, f.rig, options);
  size_t i = 0;
  double detect_ms = 0, dense_ms = 0;
  int full = 0;
  for (auto _ : state) {
    const size_t k = i % f.gray.size();
    if (k == 0) tracker.Reset();
    const FrameResult r =
        tracker.Track(f.gray[k], f.time_s[k] + (i / f.gray.size()) * 10.0);
    detect_ms += r.timings.detect_ms;
    dense_ms += r.timings.dense_ms;
    full += r.timings.full_search;
    ++i;
  }
  state.counters["detect_ms"] = detect_ms / i;
  state.counters["dense_ms"] = dense_ms / i;
  state.counters["full_share"] = double(full) / i;
}
BENCHMARK(BM_Track)
    ->ArgNames({"roi", "dense", "floor"})
    ->Args({0, 1, 0})
    ->Args({1, 1, 0})
    ->Args({1, 0, 0})
    ->Args({1, 1, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ripple::tracking
