// `ripple replay`: the live pipeline on a recording, timed by its
// timestamps, deterministic, writing an H.264 MP4 and the poses.
#include <chrono>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "app/app_common.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_source.h"
#include "app/app_video.h"
#include "app/command.h"
#include "tracking/pose_csv.h"

namespace ripple::app {
namespace {

struct ReplayArgs {
  std::string input;
  std::string camera;
  std::string rig;
  std::string out;
  std::string poses;
  std::string timing;
  std::string snapshot;
  int snapshot_frame = 0;
  double fps = 30.0;
  bool headless = false;
  PipelineArgs pipeline;
};

int RunReplay(ReplayArgs& args) {
  std::string error;
  if (!FinishPipelineOptions(&args.pipeline, args.headless ? "egl" : "glfw",
                             &error))
    return Fail(kExitBadInput, error);
  if (args.headless && args.pipeline.options.window)
    return Fail(kExitBadInput, "--headless needs --gl egl or osmesa");
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  auto source = FrameSource::Open(args.input, &error, args.fps);
  if (!source) return Fail(kExitBadInput, error);

  cv::Mat frame;
  double time_s = 0;
  auto t_cap = std::chrono::steady_clock::now();
  int code = 0;
  if (!ReadFirstFrame(source.get(), &frame, &time_s, &code, &error))
    return Fail(code, error);
  if (!MatchCameraToFrames(frame.size(), args.camera, &*camera, &error))
    return Fail(kExitBadInput, error);

  auto pipeline =
      Pipeline::Create(*camera, *rig, args.pipeline.options, &error);
  if (!pipeline) return Fail(kExitRuntime, error);
  VideoOut video;
  if (!args.out.empty() &&
      !video.Open(args.out, args.fps, frame.size(), &error))
    return Fail(kExitBadInput, error);
  tracking::PoseCsvWriter poses;
  if (!args.poses.empty() && !poses.Open(args.poses, &error))
    return Fail(kExitBadInput, error);

  StageTable table;
  const int total = source->frame_count();
  const auto t_start = std::chrono::steady_clock::now();
  int n = 0;
  int tank_tracked = 0;
  do {
    const double cap_ms = std::chrono::duration<double, std::milli>(
                              std::chrono::steady_clock::now() - t_cap)
                              .count();
    const bool snap = !args.snapshot.empty() && n == args.snapshot_frame;
    const FrameReport r = pipeline->Process(
        frame, time_s, cap_ms, /*read_back=*/video.is_open() || snap);
    if (snap && !cv::imwrite(args.snapshot, pipeline->composite()))
      return Fail(kExitBadInput,
                  "cannot write snapshot '" + args.snapshot + "'");
    table.Add(r.times);
    if (r.tracking.tank.has_pose()) ++tank_tracked;
    if (video.is_open()) video.Write(pipeline->composite());
    if (!args.poses.empty()) {
      for (const tracking::PoseRow& row :
           pipeline->tracker().ToPoseRows(r.tracking))
        if (!poses.Write(row))
          return Fail(kExitRuntime,
                      "cannot write '" + args.poses + "' (video finalized)");
    }
    if (args.pipeline.options.window) {
      pipeline->renderer().Present();
      if (pipeline->context().ShouldClose()) break;
    }
    ++n;
    const double secs = std::chrono::duration<double>(
                            std::chrono::steady_clock::now() - t_start)
                            .count();
    PrintProgress(n, total, n / std::max(secs, 1e-9));
    t_cap = std::chrono::steady_clock::now();
  } while (source->Read(&frame, &time_s));
  std::fprintf(stderr, "\n");
  // Whatever happens next, the video written so far is finalized.
  video.Close();
  poses.Close();
  std::printf("%s", table.Format("replay of " + args.input).c_str());
  std::printf("tank tracked in %d/%d frames\n", tank_tracked, n);
  if (!args.timing.empty() &&
      !table.AppendCsv(args.timing, "replay", true, &error))
    return Fail(kExitRuntime, error);
  if (!source->error().empty())
    return Fail(kExitRuntime, source->error() + " (output finalized after " +
                                  std::to_string(n) + " frames)");
  return kExitOk;
}

CommandAction SetupReplay(CLI::App* sub) {
  auto args = std::make_shared<ReplayArgs>();
  args->camera = DefaultCameraPath();
  args->rig = DefaultRigPath();
  sub->add_option("--input", args->input, "Recorded video file or image folder")
      ->required();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--out", args->out, "Output video (.mp4: H.264)");
  sub->add_option("--poses", args->poses, "Write the tracked poses (CSV)");
  sub->add_option("--timing", args->timing,
                  "Write the stage-timing table (CSV)");
  sub->add_option("--fps", args->fps,
                  "Frame rate of an image folder and of the output video")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--snapshot", args->snapshot,
                  "Write one composite frame as PNG");
  sub->add_option("--snapshot-frame", args->snapshot_frame,
                  "Index of the --snapshot frame")
      ->capture_default_str();
  sub->add_flag("--headless", args->headless,
                "No window (EGL unless --gl osmesa)");
  AddPipelineOptions(sub, &args->pipeline);
  return [args] { return RunReplay(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(
    replay, "Run the AR pipeline on a recorded video or image folder",
    SetupReplay);

}  // namespace ripple::app
