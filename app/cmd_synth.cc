// `ripple synth`: ground-truth frames of the board and the pen.
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "app/app_common.h"
#include "app/app_floor.h"
#include "app/app_video.h"
#include "app/app_wxh.h"
#include "app/command.h"
#include "bench/stats.h"
#include "tracking/pose_csv.h"
#include "tracking/synth/synth.h"
#include "tracking/synth/variant.h"

namespace ripple::app {
namespace {

struct SynthArgs {
  std::string out;
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string size;
  std::string video;
  synth::SequenceOptions seq;
  bool no_png = false;
  std::string floor;
  std::string variant = "exact";
};

int RunSynth(const SynthArgs& args) {
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  auto floor = MakeFloorOrReport(args.floor, *rig);
  if (!floor) return kExitBadInput;
  if (!args.size.empty()) {
    WxH size;
    ParseWxH(args.size, &size);  // checked by the option's validator
    *camera = camera->Scaled(size.width, size.height);
  }
  std::vector<synth::FrameSpec> frames;
  std::string error;
  if (!synth::MakeSequence(*camera, *rig, args.seq, &frames, &error))
    return Fail(kExitBadInput, error);
  if (!MakeDirectories(args.out + "/frames", &error) ||
      (!args.no_png && !MakeDirectories(args.out + "/occluders", &error)))
    return Fail(kExitBadInput, error);
  // The exact variant writes 8-bit values linear in radiance, the webcam
  // variant sRGB-encoded ones through its own lens; the camera file says
  // so, and replay honours it.
  synth::DataVariant variant;
  synth::GetDataVariant(args.variant, &variant);  // checked by the option
  *camera = synth::VariantCamera(variant, *camera);
  for (synth::FrameSpec& f : frames) synth::ApplyVariant(variant, &f.imaging);
  if (!tracking::SaveCamera(*camera, args.out + "/camera.yml", &error) ||
      !tracking::SaveRig(*rig, args.out + "/rig.yml", &error))
    return Fail(kExitBadInput, error);
  tracking::PoseCsvWriter csv;
  if (!csv.Open(args.out + "/groundtruth.csv", &error))
    return Fail(kExitBadInput, error);
  VideoOut video;
  if (!args.video.empty() &&
      !video.Open(args.video, args.seq.fps,
                  cv::Size(camera->width, camera->height), &error))
    return Fail(kExitBadInput, error);

  const synth::SceneRenderer renderer(*camera, *rig, *floor, variant.formation);
  const bench::Stopwatch watch;
  for (const synth::FrameSpec& f : frames) {
    const synth::RenderedFrame r =
        renderer.Render(f.scene, f.imaging, f.noise_seed);
    char name[64];
    std::snprintf(name, sizeof(name), "/frames/%06d.png", f.index);
    if (!args.no_png && !cv::imwrite(args.out + name, r.image,
                                     {cv::IMWRITE_PNG_COMPRESSION, 1}))
      return Fail(kExitRuntime, "cannot write '" + args.out + name + "'");
    if (!args.no_png) {
      // Ground truth of what is in front of the board: 255 a hand, 128 the
      // pen (where no hand hides it), 0 neither; a pixel counts when at
      // least half of it is covered.
      cv::Mat hands, pen;
      renderer.OccluderCoverage(f.scene, &hands, &pen);
      cv::Mat labels(hands.size(), CV_8U, cv::Scalar(0));
      labels.setTo(128, pen >= 0.5f);
      labels.setTo(255, hands >= 0.5f);
      std::snprintf(name, sizeof(name), "/occluders/%06d.png", f.index);
      if (!cv::imwrite(args.out + name, labels))
        return Fail(kExitRuntime, "cannot write '" + args.out + name + "'");
    }
    if (video.is_open()) video.Write(r.image);
    tracking::PoseRow tank;
    tank.frame = f.index;
    tank.time_s = f.time_s;
    tank.object = "tank";
    tank.status = tracking::TrackStatus::kTracked;
    tank.cam_from_object = f.scene.cam_from_tank;
    tank.faces = r.tank_tags;
    bool ok = csv.Write(tank);
    if (f.scene.tank_from_pen && rig->pen) {
      tracking::PoseRow pen = tank;
      pen.object = "pen";
      pen.cam_from_object = f.scene.cam_from_tank * *f.scene.tank_from_pen;
      pen.tip_in_tank = *f.scene.tank_from_pen * rig->pen->tip_in_pen;
      pen.faces = r.pen_tags;
      ok = ok && csv.Write(pen);
    }
    if (!ok)
      return Fail(kExitRuntime,
                  "cannot write '" + args.out + "/groundtruth.csv'");
    if ((f.index + 1) % 25 == 0 || f.index + 1 == int(frames.size()))
      std::fprintf(stderr, "\rsynth: %d/%zu frames", f.index + 1,
                   frames.size());
  }
  std::fprintf(stderr, "\n");
  std::string video_error;
  if (!video.Close(&video_error)) return Fail(kExitRuntime, video_error);
  if (!csv.Close())
    return Fail(kExitRuntime,
                "cannot finish '" + args.out + "/groundtruth.csv'");
  const double secs = watch.ElapsedS();
  std::printf(
      "synth: %zu frames of %dx%d (preset %s, seed %llu, %s floor) in %.1f s "
      "(%.1f ms/frame) -> %s\n",
      frames.size(), camera->width, camera->height, args.seq.preset.c_str(),
      static_cast<unsigned long long>(args.seq.seed),
      synth::ToString(floor->kind()), secs, 1e3 * secs / frames.size(),
      args.out.c_str());
  return kExitOk;
}

CommandAction SetupSynth(CLI::App* sub) {
  auto args = std::make_shared<SynthArgs>();
  sub->add_option("--out", args->out,
                  "Output folder (frames/, occluders/, camera.yml, rig.yml, "
                  "groundtruth.csv)")
      ->required();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--frames", args->seq.frames, "Number of frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  sub->add_option("--segment", args->seq.segment_frames,
                  "Frames per smooth segment (cuts between)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  sub->add_option(
         "--preset", args->seq.preset,
         "Motion/imaging preset: benchmark, clean, demo, hands, static")
      ->capture_default_str()
      ->check(CLI::IsMember({"benchmark", "clean", "demo", "hands", "static"}));
  sub->add_option("--variant", args->variant,
                  "Image formation: exact (exact area coverage), supersampled "
                  "(3x3 ray-cast point samples, disc defocus), srgb "
                  "(supersampled, sRGB-encoded), lens (supersampled, "
                  "distorting lens, busy table) or webcam (all of them)")
      ->capture_default_str()
      ->check(CLI::IsMember(synth::DataVariantNames()));
  sub->add_option("--seed", args->seq.seed,
                  "Random seed (output is deterministic per seed)")
      ->capture_default_str();
  sub->add_option("--fps", args->seq.fps, "Frame rate for time_s")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--size", args->size,
                  "Image size WxH (intrinsics scaled from --camera)")
      ->check(WxHValidator(WxHLimits::Size()));
  sub->add_option("--video", args->video,
                  "Also write the frames as a video (.mkv lossless, .mp4)");
  sub->add_flag("--no-png", args->no_png, "Skip the PNG frames (with --video)");
  AddFloorOption(sub, &args->floor);
  sub->footer([] {
    return synth::DescribePreset("benchmark") + synth::DescribePreset("clean") +
           synth::DescribePreset("demo") + synth::DescribePreset("static");
  }());
  return [args] { return RunSynth(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(synth,
                        "Render synthetic frames with exact ground-truth poses",
                        SetupSynth);

}  // namespace ripple::app
