// `ripple demo`: the embedded default. Synthesises the board and a pen on a
// scripted path (dip in, stroke across, pass the obstacle, lift out), runs
// the full pipeline headless, and writes out/demo.mp4, out/demo_frame.png,
// out/demo_poses.csv and out/timing.csv, printing the stage-timing table for
// the active part and for an idle tail (water at rest, pen away).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/app_common.h"
#include "app/app_floor.h"
#include "app/app_loop.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_sinks.h"
#include "app/app_synth_source.h"
#include "app/app_wxh.h"
#include "app/command.h"
#include "bench/stage_table.h"
#include "tracking/synth/synth.h"

namespace ripple::app {
namespace {

struct DemoArgs {
  std::string out = "out";
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  int frames = 240;
  int idle_frames = 60;
  uint64_t seed = 1;
  std::string size;       // WxH; empty: the camera file's
  PipelineArgs pipeline;  // --gl, water and effects
};

int RunDemo(DemoArgs args) {
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  if (!args.size.empty()) {
    WxH size;
    ParseWxH(args.size, &size);  // checked by the option's validator
    *camera = camera->Scaled(size.width, size.height);
  }
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  if (!rig->pen)
    return Fail(kExitBadInput,
                "rig file '" + args.rig + "': the demo needs a pen");
  auto floor = MakeFloorOrReport(args.pipeline.floor, *rig);
  if (!floor) return kExitBadInput;
  std::string error;
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);

  if (!FinishPipelineOptions(&args.pipeline, "egl", &error))
    return Fail(kExitBadInput, error);
  if (args.pipeline.options.occluders)
    args.pipeline.options.board_floor = *floor;
  if (args.pipeline.options.window)
    return Fail(kExitBadInput, "--gl glfw: the demo is headless (egl, osmesa)");
  const PipelineOptions& options = args.pipeline.options;
  const render::Backend* backend = &options.backend;
  auto pipeline = Pipeline::Create(*camera, *rig, options, &error);
  if (!pipeline) return Fail(kExitRuntime, error);

  synth::SequenceOptions seq;
  seq.preset = "demo";
  seq.frames = args.frames;
  seq.seed = args.seed;
  std::vector<synth::FrameSpec> frames;
  if (!synth::MakeSequence(*camera, *rig, seq, &frames, &error))
    return Fail(kExitBadInput, error);
  // A webcam's frames: sRGB-encoded (the camera file's default transfer).
  // The room's lamp, casting the real pen's shadow on the board: away from
  // the renderer's default light, so that --light auto (the default) has
  // something to find; from then on the virtual shadows, caustics and glints
  // agree with the real shadow.
  const double lamp_az = 140 * M_PI / 180, lamp_el = 55 * M_PI / 180;
  const Eigen::Vector3d lamp(std::cos(lamp_el) * std::cos(lamp_az),
                             std::cos(lamp_el) * std::sin(lamp_az),
                             std::sin(lamp_el));
  for (synth::FrameSpec& f : frames) {
    f.imaging.srgb = true;
    f.scene.light_in_tank = lamp;
    f.scene.ambient_share = 0.3;
  }
  // Idle tail: the pen has left, the same camera keeps looking.
  const synth::FrameSpec last = frames.back();
  for (int i = 0; i < args.idle_frames; ++i) {
    synth::FrameSpec f = last;
    f.index = last.index + 1 + i;
    f.time_s = f.index / seq.fps;
    f.scene.tank_from_pen.reset();
    f.scene.occluders.clear();  // the hand left with the pen
    f.noise_seed = last.noise_seed + 1 + i;
    frames.push_back(f);
  }
  const int total = static_cast<int>(frames.size());
  SynthSource source(*camera, *rig, std::move(frames), *floor);

  VideoSink video;
  const std::string video_path = args.out + "/demo.mp4";
  if (!video.Open(video_path, seq.fps, cv::Size(camera->width, camera->height),
                  &error))
    return Fail(kExitBadInput, error);
  PoseCsvSink poses;
  if (!poses.Open(args.out + "/demo_poses.csv", &error))
    return Fail(kExitBadInput, error);
  PngSink snapshot({args.out + "/demo_frame.png",
                    static_cast<int>(0.66 * args.frames), "", kExitRuntime});

  bench::StageTable active, idle;
  Eigen::Vector3d last_light = Eigen::Vector3d::UnitZ();
  bool light_from_shadow = false, light_fixed = false;
  int prepared[2] = {0, 0};  // active, idle
  FunctionSink tables([&](const LoopFrame& f, LoopStop*) {
    (f.index >= args.frames ? idle : active).Add(f.report->times);
    prepared[f.index >= args.frames] += f.report->prepared_ahead;
    last_light = f.report->light_in_tank;
    light_from_shadow = f.report->light_from_shadow;
    light_fixed = f.report->light_fixed;
    return true;
  });
  FunctionSink progress([&](const LoopFrame& f, LoopStop*) {
    if ((f.index + 1) % 30 == 0 || f.index + 1 == total)
      std::fprintf(stderr, "\rdemo: %d/%d frames", f.index + 1, total);
    return true;
  });
  FrameLoopHooks hooks;
  hooks.before_frame = [&](int index) {
    // The idle tail starts from calm water, so it shows the at-rest cost.
    if (index == args.frames) pipeline->water().Reset();
  };
  const glm::ivec2 grid = pipeline->renderer().water_grid();
  const std::string water_grid = grid.x > 0 ? ", water shaded on " +
                                                  std::to_string(grid.x) + "x" +
                                                  std::to_string(grid.y)
                                            : "";
  std::printf(
      "demo: %d active + %d idle frames of %dx%d%s, %s floor, on %s (%s)\n",
      args.frames, args.idle_frames, camera->width, camera->height,
      water_grid.c_str(), synth::ToString(floor->kind()),
      render::BackendName(*backend), pipeline->context().Description().c_str());
  FrameLoopSummary summary;
  RunFrameLoop(hooks, &source, nullptr, pipeline.get(),
               {&tables, &video, &poses, &snapshot, &progress}, &summary);
  if (summary.stopped)
    return Fail(summary.stop.exit_code, summary.stop.message);
  std::fprintf(stderr, "\n");
  std::printf("%s", active.Format("active: pen in the water").c_str());
  std::printf("%s", idle.Format("idle: water at rest, pen away").c_str());
  // Where occ and caustics ran: at the frame's start, or prepared beside
  // the last frame's render (PipelineOptions::prepare_ahead).
  std::printf(
      "real objects and caustics prepared during the frame before: %d of %d "
      "active, %d of %d idle frames\n",
      prepared[0], args.frames, prepared[1], args.idle_frames);
  auto degrees = [](const Eigen::Vector3d& l) {
    const Eigen::Vector3d u = l.normalized();
    return Eigen::Vector2d(
        std::atan2(u.y(), u.x()) * 180 / M_PI,
        std::asin(std::clamp(u.z(), -1.0, 1.0)) * 180 / M_PI);
  };
  const Eigen::Vector2d got = degrees(last_light), truth = degrees(lamp);
  std::printf(
      "light: azimuth %.1f, elevation %.1f deg (%s); the synthetic lamp: "
      "%.1f, %.1f deg, %.1f deg apart\n",
      got.x(), got.y(),
      light_fixed         ? "as given"
      : light_from_shadow ? "from the pen's shadow"
                          : "the default",
      truth.x(), truth.y(),
      std::acos(std::clamp(last_light.normalized().dot(lamp), -1.0, 1.0)) *
          180 / M_PI);
  if (const auto& day = options.renderer.daylight) {
    const render::LinearRgb& c = day->sky_rgb;
    std::printf(
        "daylight: %s, sky %.1f klx and sun %.1f klx on the board (sky "
        "share %.2f), sky colour %.2f %.2f %.2f (linear RGB, unit "
        "luminance)\n",
        day->sun_up ? "the sun is up"
                    : "the sun is below the horizon (direct light off)",
        day->sky_klx, day->sun_klx, options.renderer.optics.ambient_share, c.r,
        c.g, c.b);
  }
  if (!active.AppendCsv(args.out + "/timing.csv", "active", true, &error) ||
      !idle.AppendCsv(args.out + "/timing.csv", "idle", false, &error))
    return Fail(kExitRuntime, error);
  std::printf(
      "wrote %s (%s), %s/demo_frame.png, %s/demo_poses.csv, %s/timing.csv\n",
      video_path.c_str(), video.codec().c_str(), args.out.c_str(),
      args.out.c_str(), args.out.c_str());
  return kExitOk;
}

CommandAction SetupDemo(CLI::App* sub) {
  auto args = std::make_shared<DemoArgs>();
  sub->add_option("--out", args->out, "Output folder")->capture_default_str();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--frames", args->frames, "Frames of the scripted pen stroke")
      ->capture_default_str()
      ->check(CLI::Range(10, 100000));
  sub->add_option("--idle-frames", args->idle_frames, "Frames of the idle tail")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--size", args->size,
                  "Image size WxH, e.g. 1280x720 (intrinsics scaled from "
                  "--camera, as a webcam's other modes)")
      ->check(WxHValidator(WxHLimits::Size()));
  AddPipelineOptions(sub, &args->pipeline);
  sub->add_option("--seed", args->seed, "Noise seed")->capture_default_str();
  return [args] { return RunDemo(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(
    demo, "Run the full pipeline on an embedded synthetic scene (headless)",
    SetupDemo);

}  // namespace ripple::app
