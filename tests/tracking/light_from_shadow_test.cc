// The light from the pen's shadow against synthetic truth: the direction
// within a few degrees where the shadow falls on the board (with and
// without a reference image of the board, on plain paper and on tiles, on
// clean and on webcam-like frames), no light where there is no shadow, and
// the tracker holding the light over frames.
#include "tracking/light_from_shadow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "tests/shipped_data.h"
#include "tracking/clean_plate.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/synth/synth.h"

namespace ripple::tracking {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = M_PI / 180;

double AngleDeg(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) / kDeg;
}

// Nearest-rank percentile (p in [0, 100]) of `v`; 0 for none.
double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t rank = static_cast<size_t>(std::ceil(p / 100 * v.size()));
  return v[std::clamp<size_t>(rank, 1, v.size()) - 1];
}

// How much of the true shadow's centre line the camera sees on the board,
// metres, and whether it sees the cube's shadow: the line from the tip's
// shadow to the cube centre's, sampled every millimetre, counted where it
// is on the board, in the image and neither behind the pen nor a hand.
struct ShadowTruth {
  double visible_m = 0;
  bool end_visible = false;
};

ShadowTruth TrueShadow(const Camera& camera, const Rig& rig,
                       const synth::SceneRenderer& renderer,
                       const synth::SceneState& scene,
                       const Eigen::AlignedBox2d& board) {
  ShadowTruth truth;
  if (!scene.light_in_tank || !scene.tank_from_pen) return truth;
  Vector2d a, b;
  PenShadowLine(*rig.pen, *scene.tank_from_pen, *scene.light_in_tank, &a, &b);
  cv::Mat pen_mask, hands, pen_cover;
  DrawPenSilhouette(camera, scene.cam_from_tank * *scene.tank_from_pen,
                    rig.pen->cube_edge_m, rig.pen->shaft_radius_m,
                    rig.pen->tip_in_pen, 2.0, &pen_mask);
  renderer.OccluderCoverage(scene, &hands, &pen_cover);
  auto seen = [&](const Vector2d& p) {
    if (!board.contains(p)) return false;
    const Vector3d c = scene.cam_from_tank * Vector3d(p.x(), p.y(), 0);
    if (c.z() < 1e-3) return false;
    const Vector2d px = camera.Project(c);
    const int u = static_cast<int>(std::lround(px.x()));
    const int v = static_cast<int>(std::lround(px.y()));
    if (u < 2 || v < 2 || u >= camera.width - 2 || v >= camera.height - 2)
      return false;
    return !pen_mask.at<uint8_t>(v, u) && hands.at<float>(v, u) < 0.5f;
  };
  const double length = (b - a).norm();
  for (double t = 0; t < length; t += 0.001)
    truth.visible_m += seen(a + (b - a) * (t / length)) ? 0.001 : 0.0;
  truth.end_visible = seen(b);
  return truth;
}

// The printed board (paper at 255) as the estimator's reference image,
// 8-bit BGRA on a 1 mm grid over the sheet.
BoardReference DesignReference(const Rig& rig, const synth::FloorPattern& floor,
                               const Eigen::AlignedBox2d& sheet, bool srgb) {
  BoardReference ref;
  ref.texel_m = 0.001;
  ref.origin_m = sheet.min();
  const cv::Size size(static_cast<int>(sheet.sizes().x() / ref.texel_m),
                      static_cast<int>(sheet.sizes().y() / ref.texel_m));
  cv::Mat levels, valid;
  synth::BoardDesignLevels(rig, floor, ref.origin_m, ref.texel_m, size, srgb,
                           &levels, &valid);
  cv::Mat bgr8;
  levels.convertTo(bgr8, CV_8UC3);
  std::vector<cv::Mat> ch;
  cv::split(bgr8, ch);
  ch.push_back(valid);
  cv::merge(ch, ref.bgra);
  return ref;
}

struct RunOptions {
  std::string preset = "clean";
  int frames = 160;
  int segment_frames = 16;
  uint64_t seed = 3;
  // The printed floor: plain paper unless the test says otherwise.
  synth::FloorOptions floor = [] {
    synth::FloorOptions f;
    f.kind = synth::FloorKind::kPlain;
    return f;
  }();
  bool use_reference = false;
  bool srgb = false;       // frames sRGB-encoded (else linear)
  bool distorted = false;  // a wide lens with barrel distortion
};

struct RunResult {
  // Frames with at least 30 mm of the shadow's line in view on the board:
  // how many, how many found, their errors, and those of the frames that
  // also show the cube's shadow.
  int on_board = 0, found_on_board = 0;
  std::vector<double> errors_deg, end_errors_deg, ambient_errors;
  // Found with less of the shadow in view.
  std::vector<double> short_errors_deg;
  int found_without_shadow = 0;  // no light, flat lighting or all ambient
  int frames = 0;
  double ms_per_frame = 0;
  // The tracker's light at the end of each segment against the truth.
  std::vector<double> tracked_errors_deg;
};

// Frames of `run` with their truth; `mutate` changes each scene first.
template <typename Mutate>
RunResult RunSequence(const RunOptions& run, Mutate mutate) {
  Camera camera = test_data::DefaultCamera();
  camera.transfer =
      run.srgb ? geometry::Transfer::kSrgb : geometry::Transfer::kLinear;
  if (run.distorted) {
    camera.fx = camera.fy = 430;  // about 73 degrees across
    camera.dist = {-0.28, 0.09, 0.001, -0.0005, -0.012, 0, 0, 0};
  }
  const Rig rig = test_data::DefaultRig();
  EXPECT_TRUE(rig.pen);
  synth::FloorPattern floor;
  if (run.floor.kind != synth::FloorKind::kPlain) {
    std::string error;
    auto f = synth::FloorPattern::Create(run.floor, rig.tank, &error);
    EXPECT_TRUE(f) << error;
    if (f) floor = *f;
  }
  const synth::SceneRenderer renderer(camera, rig, floor);
  const Eigen::AlignedBox2d sheet = synth::BoardSheetRect(rig);
  const BoardReference reference = DesignReference(rig, floor, sheet, run.srgb);
  synth::SequenceOptions seq;
  seq.preset = run.preset;
  seq.frames = run.frames;
  seq.segment_frames = run.segment_frames;
  seq.seed = run.seed;
  seq.directional_light = true;
  std::vector<synth::FrameSpec> specs;
  std::string error;
  EXPECT_TRUE(synth::MakeSequence(camera, rig, seq, &specs, &error)) << error;
  const LightFromShadowOptions options;
  LightTracker tracker;
  RunResult result;
  double total_ms = 0;
  for (synth::FrameSpec& f : specs) {
    if (f.index % run.segment_frames == 0) tracker.Reset();
    mutate(&f.scene);
    synth::ImagingOptions imaging = f.imaging;
    imaging.srgb = run.srgb;
    const synth::RenderedFrame r =
        renderer.Render(f.scene, imaging, f.noise_seed);
    LightFromShadowInput input;
    input.bgr = r.image;
    input.cam_from_tank = f.scene.cam_from_tank;
    input.tank_from_pen = *f.scene.tank_from_pen;
    input.board_in_tank = sheet;
    if (run.use_reference) input.reference = &reference;
    LightEstimate estimate;
    const auto t0 = std::chrono::steady_clock::now();
    EstimateLightFromShadow(options, camera, *rig.pen, input, &estimate);
    total_ms += std::chrono::duration<double, std::milli>(
                    std::chrono::steady_clock::now() - t0)
                    .count();
    ++result.frames;
    const auto& held = tracker.Update(estimate);
    if ((f.index + 1) % run.segment_frames == 0 && f.scene.light_in_tank &&
        held)
      result.tracked_errors_deg.push_back(
          AngleDeg(held->light_in_tank, *f.scene.light_in_tank));
    const bool shadow = f.scene.light_in_tank && !f.scene.flat_lighting &&
                        f.scene.ambient_share < 1;
    if (!shadow) {
      result.found_without_shadow += estimate.found();
      continue;
    }
    const ShadowTruth truth = TrueShadow(camera, rig, renderer, f.scene, sheet);
    const double err = estimate.found() ? AngleDeg(estimate.light_in_tank,
                                                   *f.scene.light_in_tank)
                                        : 0.0;
    if (truth.visible_m < 0.03) {
      if (estimate.found()) result.short_errors_deg.push_back(err);
      continue;
    }
    ++result.on_board;
    if (!estimate.found()) continue;
    ++result.found_on_board;
    result.errors_deg.push_back(err);
    if (truth.end_visible) result.end_errors_deg.push_back(err);
    result.ambient_errors.push_back(
        std::abs(estimate.ambient_share - f.scene.ambient_share));
  }
  result.ms_per_frame = total_ms / std::max(1, result.frames);
  return result;
}

void Print(const char* name, const RunResult& r) {
  std::printf(
      "%s: %d frames, %d with >= 30 mm of shadow in view, found in %d "
      "(%.0f%%): angular error median %.2f deg, p90 %.2f deg; with the cube's "
      "shadow in view (%zu): median %.2f, p90 %.2f; ambient share error "
      "median %.3f, p90 %.3f; found with less in view: %zu, median %.2f deg; "
      "tracker at segment ends: median %.2f deg, max %.2f deg over %zu; "
      "estimator %.1f ms/frame\n",
      name, r.frames, r.on_board, r.found_on_board,
      100.0 * r.found_on_board / std::max(1, r.on_board),
      Percentile(r.errors_deg, 50), Percentile(r.errors_deg, 90),
      r.end_errors_deg.size(), Percentile(r.end_errors_deg, 50),
      Percentile(r.end_errors_deg, 90), Percentile(r.ambient_errors, 50),
      Percentile(r.ambient_errors, 90), r.short_errors_deg.size(),
      Percentile(r.short_errors_deg, 50), Percentile(r.tracked_errors_deg, 50),
      Percentile(r.tracked_errors_deg, 100), r.tracked_errors_deg.size(),
      r.ms_per_frame);
}

void NoChange(synth::SceneState*) {}

TEST(LightFromShadowTest, OptionsAreValidated) {
  std::string error;
  LightFromShadowOptions o;
  EXPECT_TRUE(o.IsValid(&error)) << error;
  o.min_elevation_rad = 1.0;
  o.max_elevation_rad = 0.5;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("elevation"), std::string::npos);
  o = LightFromShadowOptions();
  o.final_step_rad = 2 * o.coarse_step_rad;
  EXPECT_FALSE(o.IsValid(&error));
  LightTrackerOptions t;
  EXPECT_TRUE(t.IsValid(&error)) << error;
  t.min_estimates = t.window + 1;
  EXPECT_FALSE(t.IsValid(&error));
}

TEST(LightFromShadowTest, FindsTheLightOnCleanFrames) {
  const RunResult r = RunSequence(RunOptions(), NoChange);
  Print("clean, plain paper, no reference", r);
  ASSERT_GE(r.on_board, 60) << "the sequence must put shadows on the board";
  EXPECT_GE(r.found_on_board, r.on_board * 7 / 10);
  EXPECT_LE(Percentile(r.errors_deg, 50), 5.0);
  EXPECT_LE(Percentile(r.ambient_errors, 50), 0.05);
  EXPECT_LE(Percentile(r.tracked_errors_deg, 50), 5.0);
}

TEST(LightFromShadowTest, AReferenceRemovesTheTilesTexture) {
  RunOptions run;
  run.floor.kind = synth::FloorKind::kTiles;
  run.use_reference = true;
  const RunResult with = RunSequence(run, NoChange);
  Print("clean, tiles, with the design as reference", with);
  run.use_reference = false;
  const RunResult without = RunSequence(run, NoChange);
  Print("clean, tiles, no reference", without);
  ASSERT_GE(with.on_board, 60);
  EXPECT_GE(with.found_on_board, with.on_board * 7 / 10);
  EXPECT_LE(Percentile(with.errors_deg, 50), 5.0);
  EXPECT_LE(Percentile(with.ambient_errors, 50), 0.05);
}

TEST(LightFromShadowTest, WebcamLikeFrames) {
  RunOptions run;
  run.preset = "benchmark";  // noise, blur, JPEG, exposure, hands
  run.srgb = true;
  const RunResult r = RunSequence(run, NoChange);
  Print("benchmark imaging, sRGB, no reference", r);
  ASSERT_GE(r.on_board, 50);
  EXPECT_GE(r.found_on_board, r.on_board / 2);
  EXPECT_LE(Percentile(r.errors_deg, 50), 5.0);
}

TEST(LightFromShadowTest, LensDistortion) {
  RunOptions run;
  run.frames = 64;
  run.distorted = true;
  const RunResult r = RunSequence(run, NoChange);
  Print("clean, plain paper, barrel distortion", r);
  ASSERT_GE(r.on_board, 30);
  EXPECT_GE(r.found_on_board, r.on_board * 7 / 10);
  EXPECT_LE(Percentile(r.errors_deg, 50), 5.0);
}

TEST(LightFromShadowTest, NoLightWithoutAShadow) {
  RunOptions run;
  run.frames = 80;
  const RunResult all_ambient =
      RunSequence(run, [](synth::SceneState* s) { s->ambient_share = 1.0; });
  const RunResult flat =
      RunSequence(run, [](synth::SceneState* s) { s->flat_lighting = true; });
  const RunResult unlit =
      RunSequence(run, [](synth::SceneState* s) { s->light_in_tank.reset(); });
  run.floor.kind = synth::FloorKind::kTiles;
  const RunResult tiles =
      RunSequence(run, [](synth::SceneState* s) { s->light_in_tank.reset(); });
  std::printf(
      "found without a shadow in %d frames each: all ambient %d, flat %d, "
      "no light %d, no light on tiles %d\n",
      run.frames, all_ambient.found_without_shadow, flat.found_without_shadow,
      unlit.found_without_shadow, tiles.found_without_shadow);
  EXPECT_EQ(all_ambient.found_without_shadow, 0);
  EXPECT_EQ(flat.found_without_shadow, 0);
  EXPECT_EQ(unlit.found_without_shadow, 0);
  EXPECT_EQ(tiles.found_without_shadow, 0);
}

LightEstimate Found(const Vector3d& light, double ambient) {
  LightEstimate e;
  e.status = LightStatus::kFound;
  e.light_in_tank = light.normalized();
  e.ambient_share = ambient;
  e.confidence = 1.0;
  return e;
}

TEST(LightTrackerTest, HoldsTheLightThroughGapsAndOutliers) {
  LightTrackerOptions options;
  options.hold_frames = 10;
  LightTracker tracker(options);
  const Vector3d truth = Vector3d(0.4, -0.3, 0.8).normalized();
  LightEstimate none;
  EXPECT_FALSE(tracker.Update(none));
  EXPECT_FALSE(tracker.Update(Found(truth + Vector3d(0.02, 0, 0), 0.3)));
  EXPECT_FALSE(tracker.Update(Found(truth - Vector3d(0.02, 0, 0), 0.4)));
  ASSERT_TRUE(tracker.Update(Found(truth, 0.35)));
  EXPECT_LT(AngleDeg(tracker.current()->light_in_tank, truth), 0.5);
  EXPECT_NEAR(tracker.current()->ambient_share, 0.35, 1e-9);
  // A wrong estimate (the other elevation) and unconfident ones do not move
  // it.
  tracker.Update(Found(Vector3d(0.4, -0.3, 0.2), 0.9));
  LightEstimate weak = Found(Vector3d(-1, 0, 0.3), 0.9);
  weak.confidence = 0.1;
  tracker.Update(weak);
  ASSERT_TRUE(tracker.current());
  EXPECT_LT(AngleDeg(tracker.current()->light_in_tank, truth), 0.5);
  EXPECT_EQ(tracker.current()->inliers, 3);
  // Frames without a shadow hold it, for hold_frames.
  for (int i = 0; i < 9; ++i) EXPECT_TRUE(tracker.Update(none));
  EXPECT_EQ(tracker.current()->frames_since_estimate, 10);
  EXPECT_FALSE(tracker.Update(none));
  tracker.Update(Found(truth, 0.35));
  EXPECT_FALSE(tracker.current()) << "a dropped light starts over";
  tracker.Reset();
  EXPECT_FALSE(tracker.current());
}

}  // namespace
}  // namespace ripple::tracking
