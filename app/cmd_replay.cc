// `ripple replay`: the live pipeline on a recording, timed by its
// timestamps, deterministic, writing an H.264 MP4 and the poses.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "app/app_common.h"
#include "app/app_loop.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_sinks.h"
#include "app/app_source.h"
#include "app/command.h"
#include "bench/stage_table.h"
#include "bench/stats.h"

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
  if (!SetBoardFloor(&args.pipeline, *rig)) return kExitBadInput;
  auto source = FrameSource::Open(args.input, &error, args.fps);
  if (!source) return Fail(kExitBadInput, error);

  SourceFrame first;
  int code = 0;
  const bench::Stopwatch first_watch;
  if (!ReadFirstFrame(source.get(), &first.bgr, &first.time_s, &code, &error))
    return Fail(code, error);
  first.cap_ms = first_watch.ElapsedMs();
  if (!MatchCameraToFrames(first.bgr.size(), args.camera, &*camera, &error))
    return Fail(kExitBadInput, error);

  auto pipeline =
      Pipeline::Create(*camera, *rig, args.pipeline.options, &error);
  if (!pipeline) return Fail(kExitRuntime, error);
  // --out DIR/ (or an existing folder): lossless PNG frames; else a video.
  const bool out_folder =
      !args.out.empty() &&
      (args.out.back() == '/' || std::filesystem::is_directory(args.out));
  VideoSink video;
  std::unique_ptr<PngFolderSink> frames_out;
  if (out_folder) {
    std::string folder = args.out;
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    if (!MakeDirectories(folder, &error)) return Fail(kExitBadInput, error);
    frames_out = std::make_unique<PngFolderSink>(folder);
  } else if (!args.out.empty() &&
             !video.Open(args.out, args.fps, first.bgr.size(), &error)) {
    return Fail(kExitBadInput, error);
  }
  PoseCsvSink poses;
  if (!args.poses.empty() && !poses.Open(args.poses, &error))
    return Fail(kExitBadInput, error);

  bench::StageTable table;
  int tank_tracked = 0;
  FunctionSink stats([&](const LoopFrame& f, LoopStop*) {
    table.Add(f.report->times);
    if (f.report->tracking.tank.has_pose()) ++tank_tracked;
    return true;
  });
  const int total = source->frame_count();
  const bench::Stopwatch run_watch;
  FunctionSink progress([&](const LoopFrame& f, LoopStop*) {
    PrintProgress(f.index + 1, total,
                  (f.index + 1) / std::max(run_watch.ElapsedS(), 1e-9));
    return true;
  });
  std::vector<FrameSink*> sinks;
  std::unique_ptr<PngSink> snapshot;
  if (!args.snapshot.empty()) {
    snapshot = std::make_unique<PngSink>(PngSink::Options{
        args.snapshot, args.snapshot_frame, "snapshot", kExitBadInput});
    sinks.push_back(snapshot.get());
  }
  sinks.push_back(&stats);
  sinks.push_back(&video);
  if (frames_out) sinks.push_back(frames_out.get());
  if (!args.poses.empty()) sinks.push_back(&poses);
  WindowSink window;
  if (args.pipeline.options.window) sinks.push_back(&window);
  sinks.push_back(&progress);

  FrameLoopSummary summary;
  RunFrameLoop(FrameLoopHooks(), source.get(), &first, pipeline.get(), sinks,
               &summary);
  if (summary.stopped && summary.stop.exit_code != kExitOk)
    return Fail(summary.stop.exit_code, summary.stop.message);
  std::fprintf(stderr, "\n");
  const int n = summary.frames;
  std::printf("%s", table.Format("replay of " + args.input).c_str());
  std::printf("tank tracked in %d/%d frames\n", tank_tracked, n);
  if (!args.timing.empty() &&
      !table.AppendCsv(args.timing, "replay", true, &error))
    return Fail(kExitRuntime, error);
  if (!summary.source_error.empty())
    return Fail(kExitRuntime, summary.source_error +
                                  " (output finalized after " +
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
  sub->add_option("--out", args->out,
                  "Output video (.mp4: H.264), or a folder (ending in /) for "
                  "lossless PNG frames");
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
