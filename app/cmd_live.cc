// `ripple live`: the webcam sees the board and the pen; the water appears in
// a GLFW window and reacts to the pen tip. The camera is a FrameSource, the
// keys and the HUD belong to the LiveSession (app/app_live_session.h); `h`
// lists the keys.
#include <cmath>
#include <cstdio>

#include "app/app_common.h"
#include "app/app_live_session.h"
#include "app/app_loop.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_sinks.h"
#include "app/app_source.h"
#include "app/app_wxh.h"
#include "app/command.h"

namespace ripple::app {
namespace {

struct LiveArgs {
  std::string input = "0";
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string size;
  double fps = 30;
  std::string record_raw;
  std::string out_dir = ".";
  PipelineArgs pipeline;
};

int RunLive(LiveArgs& args) {
  std::string error;
  if (!FinishPipelineOptions(&args.pipeline, "glfw", &error))
    return Fail(kExitBadInput, error);
  // Screenshots read the FBO back at any time, when the camera's frame may
  // be gone: the whole frame is drawn.
  args.pipeline.options.renderer.full_frame_output = true;
  // Reading the camera's next frame before rendering this one would wait
  // for it: no overlap.
  args.pipeline.options.overlap_tracking = false;
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  if (!SetBoardFloor(&args.pipeline, *rig)) return kExitBadInput;
  WxH want{camera->width, camera->height};
  if (!args.size.empty()) ParseWxH(args.size, &want);  // validated

  FrameSourceOptions capture;
  capture.camera_width = want.width;
  capture.camera_height = want.height;
  capture.camera_fps = args.fps;
  capture.camera_newest_frame = true;
  capture.camera_retries = 29;  // about 0.3 s without a frame: lost
  auto source = FrameSource::Open(args.input, capture, &error);
  if (!source)
    return Fail(kExitBadInput, "no camera at '" + args.input +
                                   "' (try --input 0 or /dev/video0)");
  SourceFrame first;
  if (!ReadSourceFrame(source.get(), &first))
    return Fail(kExitRuntime,
                "camera '" + args.input + "' opened but delivers no frames");
  if (first.bgr.cols != want.width || first.bgr.rows != want.height)
    std::fprintf(
        stderr,
        "ripple: warning: asked the camera for %dx%d, it delivers %dx%d\n",
        want.width, want.height, first.bgr.cols, first.bgr.rows);
  const double got_fps = source->reported_fps();
  if (got_fps > 0 && std::abs(got_fps - args.fps) > 0.5)
    std::fprintf(
        stderr,
        "ripple: warning: asked for %.1f fps, the camera reports %.1f\n",
        args.fps, got_fps);
  if (!MatchCameraToFrames(first.bgr.size(), args.camera, &*camera, &error))
    return Fail(kExitBadInput, error);

  auto pipeline =
      Pipeline::Create(*camera, *rig, args.pipeline.options, &error);
  if (!pipeline) return Fail(kExitRuntime, error);
  RawSink raw;
  if (!args.record_raw.empty() && !raw.recorder().Open(args.record_raw, &error))
    return Fail(kExitBadInput, error);

  LiveSessionOptions options;
  options.out_dir = args.out_dir;
  options.fps = args.fps;
  options.frame_size = first.bgr.size();
  LiveSession session(options, pipeline.get(), &raw);
  FrameLoopSummary summary;
  RunFrameLoop(session.Hooks(), source.get(), &first, pipeline.get(),
               session.Sinks(), &summary);
  // The loop has finalized the recordings, whatever ended the session.
  std::printf("%s", session.table().Format("live").c_str());
  if (summary.stopped && summary.stop.exit_code != kExitOk)
    return Fail(summary.stop.exit_code, summary.stop.message);
  if (!summary.source_error.empty())
    return Fail(kExitRuntime, summary.source_error);
  // A camera never ends by itself; an input that does (a video file) is a
  // lost camera too.
  if (!summary.stopped)
    return Fail(kExitRuntime,
                "camera '" + args.input + "' lost (no frame for 30 reads)");
  return kExitOk;
}

CommandAction SetupLive(CLI::App* sub) {
  auto args = std::make_shared<LiveArgs>();
  sub->add_option("--input", args->input, "Camera index or device path")
      ->capture_default_str();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--size", args->size,
                  "Capture size WxH (default: the calibration's)")
      ->check(WxHValidator(WxHLimits::Size()));
  sub->add_option("--fps", args->fps, "Capture frame rate")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  sub->add_option("--record-raw", args->record_raw,
                  "Record the raw camera frames losslessly (PNG + "
                  "timestamps.csv) into DIR");
  sub->add_option("--out-dir", args->out_dir,
                  "Folder for screenshots and recordings")
      ->capture_default_str();
  AddPipelineOptions(sub, &args->pipeline);
  return [args] { return RunLive(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(live, "Live AR water from a webcam in a window",
                        SetupLive);

}  // namespace ripple::app
