// Time of the clean plate per frame (mask + learning) on the demo's view,
// 640x480, a hand over the tank and one on the pen; frames rendered
// outside the timed loop.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/clean_plate.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"
#include "tracking/synth/synth.h"

namespace ripple::tracking {
namespace {

struct Frames {
  Camera camera;
  Rig rig;
  std::vector<cv::Mat> images, excludes, shafts;
  std::vector<Pose> poses;
  std::vector<cv::Rect> windows;
};

const Frames& GetFrames() {
  static const Frames frames = [] {
    Frames f;
    std::string error;
    f.camera = *LoadCamera(
        std::string(RIPPLE_SOURCE_DIR) + "/data/camera/default_640x480.yml",
        &error);
    f.rig = *LoadRig(std::string(RIPPLE_SOURCE_DIR) + "/data/rig/default.yml",
                     &error);
    synth::SequenceOptions seq;
    seq.preset = "hands";
    seq.frames = 40;
    seq.segment_frames = 40;
    std::vector<synth::FrameSpec> specs;
    synth::MakeSequence(f.camera, f.rig, seq, &specs, &error);
    const synth::SceneRenderer renderer(f.camera, f.rig);
    for (const synth::FrameSpec& s : specs) {
      f.images.push_back(
          renderer.Render(s.scene, s.imaging, s.noise_seed).image);
      // The pen's masks as the pipeline gives them (its 1 mm margin).
      cv::Mat mask, shaft;
      if (s.scene.tank_from_pen)
        DrawPenPlateMasks(f.camera,
                          s.scene.cam_from_tank * *s.scene.tank_from_pen,
                          f.rig.pen->cube_edge_m, f.rig.pen->shaft_radius_m,
                          f.rig.pen->tip_in_pen, 0.001, &mask, &shaft);
      f.excludes.push_back(mask);
      f.shafts.push_back(shaft);
      f.poses.push_back(s.scene.cam_from_tank);
      f.windows.push_back(TankWindow(f.camera, s.scene.cam_from_tank,
                                     f.rig.tank.size_x_m, f.rig.tank.size_y_m,
                                     f.rig.tank.wall_height_m, 4));
    }
    return f;
  }();
  return frames;
}

// surround 0: the board the tank's box hides; 1: also the board around it
// that the renderer's tank shadow changes, with the mask grown by a pixel,
// as the pipeline sets it then (render::TankShadowReach: the 3 mm glass and
// two wall heights).
void BM_CleanPlateProcess(benchmark::State& state) {
  const Frames& f = GetFrames();
  CleanPlateOptions options;
  if (state.range(0)) {
    options.surround_m = 0.003 + 2.0 * f.rig.tank.wall_height_m;
    options.margin_m = std::max(options.margin_m, options.surround_m);
    options.grow_px = 1;
  }
  CleanPlate plate(f.camera, f.rig.tank.size_x_m, f.rig.tank.size_y_m,
                   f.rig.tank.wall_height_m, options);
  cv::Mat levels, valid;
  const cv::Point2d o = plate.plate_origin_m();
  synth::BoardDesignLevels(f.rig, synth::FloorPattern(), {o.x, o.y},
                           plate.texel_m(), plate.plate_size(), false, &levels,
                           &valid);
  plate.SetBoardPrior(levels, valid);
  size_t i = 0;
  double texels = 0;
  for (auto _ : state) {
    const size_t k = i++ % f.images.size();
    texels += plate.Process(f.images[k], f.poses[k], f.excludes[k], f.shafts[k])
                  .visited_texels;
  }
  state.counters["texels"] = texels / std::max<size_t>(i, 1);
  state.counters["window_px"] = f.windows[0].area();
}
BENCHMARK(BM_CleanPlateProcess)
    ->ArgName("surround")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ripple::tracking
