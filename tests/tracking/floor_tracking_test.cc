// The printed tank floor does not change what the tracker sees: the same
// synthetic frames rendered on the plain and on the tiled floor give the
// same detected tags and the same pose errors against ground truth.
//
// The floor is paper-separated from the board tags, so without imaging
// effects (the clean preset) their pixels and corners are the same; the pen
// moves in front of the floor, so its faces' surroundings legitimately
// differ. With blur, noise and JPEG (the benchmark preset) the floor still
// reaches the tags through 8x8 JPEG blocks and the blur kernels, moving
// corners by hundredths of a pixel: poses then differ frame by frame at the
// noise level, and their statistics agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "tests/shipped_data.h"
#include "tests/tracking/synth_sequence.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/synth/synth.h"
#include "tracking/tag_detector.h"
#include "tracking/tracker.h"

namespace ripple::tracking {
namespace {

constexpr double kDeg = M_PI / 180.0;

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// What one floor gives over a sequence.
struct FloorRun {
  // Per frame: the raw detector's board and pen tag ids.
  std::vector<std::set<int>> tank_ids, pen_ids;
  int foreign = 0;  // detections of ids not in the rig
  int tank_tracked = 0, pen_tracked = 0;
  // Errors against ground truth over the tracked frames.
  std::vector<double> tank_rot_deg, tank_mm, pen_rot_deg, tip_mm;
  std::map<int, double> tip_mm_by_frame;  // the same, by frame index

  int Tags() const {
    int n = 0;
    for (size_t i = 0; i < tank_ids.size(); ++i)
      n += tank_ids[i].size() + pen_ids[i].size();
    return n;
  }
};

FloorRun TrackOnFloor(synth::FloorKind kind,
                      const std::vector<synth::FrameSpec>& specs) {
  const Camera camera = test_data::DefaultCamera();
  const Rig rig = test_data::DefaultRig();
  synth::FloorOptions options;
  options.kind = kind;
  std::string error;
  const auto floor = synth::FloorPattern::Create(options, rig.tank, &error);
  EXPECT_TRUE(floor) << error;
  const synth::SceneRenderer renderer(camera, rig, *floor);
  TagDetectorOptions detector_options;
  detector_options.family = rig.family;
  TagDetector detector(detector_options);
  Tracker tracker(camera, rig, TrackerOptions{});
  FloorRun run;
  for (const synth::FrameSpec& spec : specs) {
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    run.tank_ids.emplace_back();
    run.pen_ids.emplace_back();
    for (const TagDetection& d : detector.Detect(frame.image)) {
      if (rig.FindTankTag(d.id))
        run.tank_ids.back().insert(d.id);
      else if (rig.FindPenFace(d.id))
        run.pen_ids.back().insert(d.id);
      else
        ++run.foreign;
    }
    const FrameResult r = tracker.Track(frame.image, spec.time_s);
    if (r.tank.status == TrackStatus::kTracked) {
      ++run.tank_tracked;
      run.tank_rot_deg.push_back(
          RotationDistance(*r.tank.cam_from_object, spec.scene.cam_from_tank) /
          kDeg);
      run.tank_mm.push_back(1e3 * (r.tank.cam_from_object->translation -
                                   spec.scene.cam_from_tank.translation)
                                      .norm());
    }
    if (r.pen.status == TrackStatus::kTracked && spec.scene.tank_from_pen) {
      ++run.pen_tracked;
      const Pose cam_from_pen =
          spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
      run.pen_rot_deg.push_back(
          RotationDistance(*r.pen.cam_from_object, cam_from_pen) / kDeg);
      if (r.tip_in_tank) {
        const Eigen::Vector3d tip =
            *spec.scene.tank_from_pen * rig.pen->tip_in_pen;
        run.tip_mm.push_back(1e3 * (*r.tip_in_tank - tip).norm());
        run.tip_mm_by_frame[spec.index] = run.tip_mm.back();
      }
    }
  }
  return run;
}

struct Comparison {
  FloorRun plain, tiles;
  int same_tank_frames = 0, same_pen_frames = 0, frames = 0;
};

Comparison Compare(const std::string& preset, int frames, uint64_t seed) {
  const std::vector<synth::FrameSpec> specs =
      test_data::SynthSpecs(test_data::DefaultCamera(), test_data::DefaultRig(),
                            preset, frames, 20, seed);
  Comparison c;
  c.frames = static_cast<int>(specs.size());
  c.plain = TrackOnFloor(synth::FloorKind::kPlain, specs);
  c.tiles = TrackOnFloor(synth::FloorKind::kTiles, specs);
  for (size_t i = 0; i < specs.size(); ++i) {
    c.same_tank_frames += c.plain.tank_ids[i] == c.tiles.tank_ids[i];
    c.same_pen_frames += c.plain.pen_ids[i] == c.tiles.pen_ids[i];
  }
  for (const auto& [name, r] :
       {std::pair{"plain", &c.plain}, std::pair{"tiles", &c.tiles}})
    std::printf(
        "%s, %s floor: %d tags detected (%d foreign); tank tracked %d, rot "
        "median %.4f deg, %.3f mm; pen tracked %d, rot median %.3f deg, tip "
        "median %.3f mm\n",
        preset.c_str(), name, r->Tags(), r->foreign, r->tank_tracked,
        Median(r->tank_rot_deg), Median(r->tank_mm), r->pen_tracked,
        Median(r->pen_rot_deg), Median(r->tip_mm));
  std::printf("%s: same board tags in %d/%d frames, same pen tags in %d/%d\n",
              preset.c_str(), c.same_tank_frames, c.frames, c.same_pen_frames,
              c.frames);
  return c;
}

TEST(FloorTrackingTest, CleanFramesSeeTheSameBoard) {
  const Comparison c = Compare("clean", 30, 1);
  ASSERT_EQ(c.frames, 30);
  EXPECT_EQ(c.plain.foreign, 0);
  EXPECT_EQ(c.tiles.foreign, 0);  // the tiles never decode as tags
  EXPECT_EQ(c.same_tank_frames, c.frames);
  EXPECT_GE(c.same_pen_frames, c.frames - 2);
  EXPECT_NEAR(c.tiles.Tags(), c.plain.Tags(), 2);
  EXPECT_EQ(c.tiles.tank_tracked, c.plain.tank_tracked);
  EXPECT_EQ(c.tiles.pen_tracked, c.plain.pen_tracked);
  EXPECT_NEAR(Median(c.tiles.tank_rot_deg), Median(c.plain.tank_rot_deg), 2e-4);
  EXPECT_NEAR(Median(c.tiles.tank_mm), Median(c.plain.tank_mm), 2e-3);
  EXPECT_NEAR(Median(c.tiles.pen_rot_deg), Median(c.plain.pen_rot_deg), 0.01);
  // The tip frame by frame: the same frames and noise on either floor, so
  // the paired difference is the floor's alone. (The medians moved apart by
  // 0.027 mm when the plain floor's frame 4 went from 0.157 to 0.137 mm,
  // the same on tiles, and the ranks around the median shifted.) Measured:
  // median 0.000 mm, mean 0.008 mm, largest 0.130 mm (frame 24, the tip
  // over a grout line).
  std::vector<double> tip_diff_mm;
  for (const auto& [frame, plain_mm] : c.plain.tip_mm_by_frame) {
    const auto tiles = c.tiles.tip_mm_by_frame.find(frame);
    if (tiles != c.tiles.tip_mm_by_frame.end())
      tip_diff_mm.push_back(std::abs(tiles->second - plain_mm));
  }
  ASSERT_GE(tip_diff_mm.size(), 28u);
  double mean_diff_mm = 0;
  for (double d : tip_diff_mm) mean_diff_mm += d / tip_diff_mm.size();
  std::printf(
      "clean: tip difference tiles - plain per frame: median %.4f mm, "
      "mean %.4f mm, largest %.4f mm\n",
      Median(tip_diff_mm), mean_diff_mm,
      *std::max_element(tip_diff_mm.begin(), tip_diff_mm.end()));
  EXPECT_LT(Median(tip_diff_mm), 0.005);
  EXPECT_LT(mean_diff_mm, 0.02);
  EXPECT_NEAR(Median(c.tiles.tip_mm), Median(c.plain.tip_mm), 0.04);
}

TEST(FloorTrackingTest, BenchmarkFramesGiveTheSameErrors) {
  const Comparison c = Compare("benchmark", 60, 1);
  ASSERT_EQ(c.frames, 60);
  EXPECT_EQ(c.plain.foreign, 0);
  EXPECT_EQ(c.tiles.foreign, 0);
  EXPECT_GE(c.same_tank_frames, c.frames - 3);
  EXPECT_GE(c.same_pen_frames, c.frames - 3);
  EXPECT_NEAR(c.tiles.Tags(), c.plain.Tags(), 0.01 * c.plain.Tags());
  EXPECT_EQ(c.tiles.tank_tracked, c.plain.tank_tracked);
  EXPECT_NEAR(c.tiles.pen_tracked, c.plain.pen_tracked, 1);
  // Medians over 60 frames of errors that differ per frame at the noise
  // level: within 10% (tank) and 15% (pen) of their own size, the tank's
  // rotation within 0.003 deg at least (about twice the spread of a median
  // over 60 frames of errors near 0.008 deg).
  const double tank_rot = Median(c.plain.tank_rot_deg);
  EXPECT_NEAR(Median(c.tiles.tank_rot_deg), tank_rot,
              std::max(0.1 * tank_rot, 0.003));
  const double tank_mm = Median(c.plain.tank_mm);
  EXPECT_NEAR(Median(c.tiles.tank_mm), tank_mm, 0.1 * tank_mm);
  const double tip_mm = Median(c.plain.tip_mm);
  EXPECT_NEAR(Median(c.tiles.tip_mm), tip_mm, 0.15 * tip_mm);
  const double pen_rot = Median(c.plain.pen_rot_deg);
  EXPECT_NEAR(Median(c.tiles.pen_rot_deg), pen_rot, 0.15 * pen_rot);
}

}  // namespace
}  // namespace ripple::tracking
