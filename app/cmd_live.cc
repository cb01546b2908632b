// `ripple live`: the webcam sees the board and the pen; the water appears in
// a GLFW window and reacts to the pen tip. Keys: `h` lists them.
#include <chrono>
#include <cstdio>
#include <deque>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <random>
#include <thread>

#include "app/app_common.h"
#include "app/app_options.h"
#include "app/app_pipeline.h"
#include "app/app_raw.h"
#include "app/app_video.h"
#include "app/command.h"

namespace ripple::app {
namespace {

using Clock = std::chrono::steady_clock;

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

const char* kHelp[] = {
    "h  this help",         "v/V viscosity down/up", "r/R radius down/up",
    "f/F force down/up",    "c  caustics on/off",    "s  shadows on/off",
    "e  reflection on/off", "t  refraction on/off",  "o/O add/remove obstacle",
    "w  reset the water",   "p  screenshot (PNG)",   "m  record composite MP4",
    "k  record raw camera", "space  pause",          "q/Esc  quit",
};

bool OpenCamera(const std::string& input, cv::VideoCapture* cap) {
  const bool index = !input.empty() &&
                     input.find_first_not_of("0123456789") == std::string::npos;
  try {
    if (index)
      return cap->open(std::stoi(input), cv::CAP_ANY) && cap->isOpened();
    return cap->open(input, cv::CAP_ANY) && cap->isOpened();
  } catch (const cv::Exception&) {
    return false;
  }
}

// Median of the last frames' stage times, for the HUD.
StageTimes RecentMedian(const std::deque<StageTimes>& recent) {
  StageTimes m;
  double StageTimes::*fields[] = {&StageTimes::cap,      &StageTimes::det,
                                  &StageTimes::pose,     &StageTimes::sim,
                                  &StageTimes::caustics, &StageTimes::shadow,
                                  &StageTimes::drw,      &StageTimes::total};
  for (auto f : fields) {
    std::vector<double> v;
    for (const StageTimes& t : recent) v.push_back(t.*f);
    m.*f = Percentile(v, 50);
  }
  return m;
}

cv::Mat DrawHud(const std::vector<std::string>& lines) {
  const int line_h = 18, width = 470;
  cv::Mat hud(int(lines.size()) * line_h + 10, width, CV_8UC4,
              cv::Scalar(0, 0, 0, 150));
  for (size_t i = 0; i < lines.size(); ++i)
    cv::putText(hud, lines[i], cv::Point(8, 18 + int(i) * line_h),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(255, 255, 255, 255),
                1, cv::LINE_AA);
  return hud;
}

int RunLive(LiveArgs& args) {
  std::string error;
  if (!FinishPipelineOptions(&args.pipeline, "glfw", &error))
    return Fail(kExitBadInput, error);
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  int want_w = camera->width, want_h = camera->height;
  if (!args.size.empty()) {
    char x = 0;
    std::istringstream in(args.size);
    if (!(in >> want_w >> x >> want_h) || x != 'x' || want_w <= 0 ||
        want_h <= 0)
      return Fail(kExitBadInput,
                  "--size '" + args.size + "': expected WIDTHxHEIGHT");
  }

  cv::VideoCapture cap;
  if (!OpenCamera(args.input, &cap))
    return Fail(kExitBadInput, "no camera at '" + args.input +
                                   "' (try --input 0 or /dev/video0)");
  // A one-frame buffer keeps the latency low: we always get the newest frame.
  cap.set(cv::CAP_PROP_BUFFERSIZE, 1);
  cap.set(cv::CAP_PROP_FRAME_WIDTH, want_w);
  cap.set(cv::CAP_PROP_FRAME_HEIGHT, want_h);
  cap.set(cv::CAP_PROP_FPS, args.fps);
  cv::Mat frame;
  if (!cap.read(frame) || frame.empty())
    return Fail(kExitRuntime,
                "camera '" + args.input + "' opened but delivers no frames");
  if (frame.cols != want_w || frame.rows != want_h)
    std::fprintf(
        stderr,
        "ripple: warning: asked the camera for %dx%d, it delivers %dx%d\n",
        want_w, want_h, frame.cols, frame.rows);
  const double got_fps = cap.get(cv::CAP_PROP_FPS);
  if (got_fps > 0 && std::abs(got_fps - args.fps) > 0.5)
    std::fprintf(
        stderr,
        "ripple: warning: asked for %.1f fps, the camera reports %.1f\n",
        args.fps, got_fps);
  if (!MatchCameraToFrames(frame.size(), args.camera, &*camera, &error))
    return Fail(kExitBadInput, error);

  auto pipeline =
      Pipeline::Create(*camera, *rig, args.pipeline.options, &error);
  if (!pipeline) return Fail(kExitRuntime, error);
  RawRecorder raw;
  if (!args.record_raw.empty() && !raw.Open(args.record_raw, &error))
    return Fail(kExitBadInput, error);
  VideoOut composite_video;

  StageTable table;
  std::deque<StageTimes> recent;
  bool paused = false, help = false, quit = false;
  int shots = 0, videos = 0, raws = 0, failures = 0;
  std::string status_line;
  std::mt19937 rng(1);
  const auto t_start = Clock::now();
  auto t_hud = t_start - std::chrono::seconds(1);
  auto t_cap = Clock::now();
  FrameReport last;
  std::deque<double> frame_times;
  int exit_code = kExitOk;
  std::string exit_message;

  bool fresh = true;  // `frame` is a new camera frame
  while (!quit && !pipeline->context().ShouldClose()) {
    const double time_s =
        std::chrono::duration<double>(Clock::now() - t_start).count();
    if (!paused && fresh) {
      const double cap_ms =
          std::chrono::duration<double, std::milli>(Clock::now() - t_cap)
              .count();
      FrameReport r = pipeline->Process(
          frame, time_s, cap_ms, /*read_back=*/composite_video.is_open());
      if (!r.rendered)
        pipeline->renderer().RenderVideoOnly(
            {frame.data, frame.cols, frame.rows, static_cast<int>(frame.step)});
      table.Add(r.times);
      recent.push_back(r.times);
      if (recent.size() > 30) recent.pop_front();
      frame_times.push_back(time_s);
      if (frame_times.size() > 30) frame_times.pop_front();
      if (raw.is_open() && !raw.Write(frame, time_s, &error)) {
        exit_code = kExitRuntime;
        exit_message = error;
        break;
      }
      if (composite_video.is_open())
        composite_video.Write(pipeline->composite());
      last = r;
    } else {
      pipeline->context().PollEvents();
    }

    // HUD, a few times per second.
    if (Clock::now() - t_hud > std::chrono::milliseconds(250)) {
      t_hud = Clock::now();
      const StageTimes m = RecentMedian(recent);
      const double fps = frame_times.size() > 1
                             ? (frame_times.size() - 1) /
                                   (frame_times.back() - frame_times.front())
                             : 0.0;
      const sim::WaterOptions& w = pipeline->water().options();
      const render::Effects& fx = pipeline->effects();
      char buf[256];
      std::vector<std::string> lines;
      std::snprintf(buf, sizeof(buf), "%.1f fps%s   tank %s   pen %s", fps,
                    paused ? " (paused)" : "",
                    tracking::ToString(last.tracking.tank.status),
                    tracking::ToString(last.tracking.pen.status));
      lines.push_back(buf);
      std::snprintf(buf, sizeof(buf),
                    "ms  cap %.1f det %.1f pose %.1f sim %.1f caus %.1f shad "
                    "%.1f drw %.1f tot %.1f",
                    m.cap, m.det, m.pose, m.sim, m.caustics, m.shadow, m.drw,
                    m.total);
      lines.push_back(buf);
      std::snprintf(
          buf, sizeof(buf),
          "viscosity %.2f/s  radius %.1f mm  force %.1f m/s2  obstacles %d",
          w.viscosity_per_s, 1e3 * w.pen_radius_m, w.pen_strength_m_per_s2,
          pipeline->num_obstacles());
      lines.push_back(buf);
      std::snprintf(buf, sizeof(buf),
                    "caustics %s shadows %s reflection %s refraction %s%s%s",
                    fx.caustics ? "on" : "off", fx.shadows ? "on" : "off",
                    fx.reflection ? "on" : "off", fx.refraction ? "on" : "off",
                    composite_video.is_open() ? "  REC mp4" : "",
                    raw.is_open() ? "  REC raw" : "");
      lines.push_back(buf);
      if (!status_line.empty()) lines.push_back(status_line);
      if (help) {
        for (const char* h : kHelp) lines.push_back(h);
      } else {
        lines.push_back("h: keys");
      }
      const cv::Mat hud = DrawHud(lines);
      pipeline->renderer().SetOverlay(hud.data, hud.cols, hud.rows,
                                      static_cast<int>(hud.step));
    }
    pipeline->renderer().Present();

    // Keys.
    for (int key : pipeline->context().TakeTypedKeys()) {
      sim::WaterOptions w = pipeline->water().options();
      bool water_changed = false;
      switch (key) {
        case 'h':
          help = !help;
          break;
        case 'v':
          w.viscosity_per_s /= 1.5;
          water_changed = true;
          break;
        case 'V':
          w.viscosity_per_s = std::max(0.1, w.viscosity_per_s * 1.5);
          water_changed = true;
          break;
        case 'r':
          w.pen_radius_m /= 1.25;
          water_changed = true;
          break;
        case 'R':
          w.pen_radius_m *= 1.25;
          water_changed = true;
          break;
        case 'f':
          w.pen_strength_m_per_s2 /= 1.5;
          water_changed = true;
          break;
        case 'F':
          w.pen_strength_m_per_s2 *= 1.5;
          water_changed = true;
          break;
        case 'c':
          pipeline->effects().caustics = !pipeline->effects().caustics;
          break;
        case 's':
          pipeline->effects().shadows = !pipeline->effects().shadows;
          break;
        case 'e':
          pipeline->effects().reflection = !pipeline->effects().reflection;
          break;
        case 't':
          pipeline->effects().refraction = !pipeline->effects().refraction;
          break;
        case 'o': {
          // At the pen tip if it is in the tank, else somewhere inside.
          double x, y;
          if (last.tracking.tip_in_tank) {
            x = last.tracking.tip_in_tank->x();
            y = last.tracking.tip_in_tank->y();
          } else {
            std::uniform_real_distribution<double> ux(-0.35, 0.35);
            x = ux(rng) * rig->tank.size_x_m;
            y = ux(rng) * rig->tank.size_y_m;
          }
          status_line =
              pipeline->AddObstacleAt(x, y, &error) ? "obstacle added" : error;
          break;
        }
        case 'O':
          status_line = pipeline->RemoveLastObstacle() ? "obstacle removed"
                                                       : "no obstacle";
          break;
        case 'w':
          pipeline->water().Reset();
          status_line = "water reset";
          break;
        case 'p': {
          cv::Mat shot(frame.size(), CV_8UC3);
          pipeline->renderer().ReadBgr(shot.data, static_cast<int>(shot.step));
          const std::string path =
              args.out_dir + "/ripple_shot_" + std::to_string(shots++) + ".png";
          status_line = cv::imwrite(path, shot) ? "saved " + path
                                                : "cannot write " + path;
          break;
        }
        case 'm':
          if (composite_video.is_open()) {
            composite_video.Close();
            status_line = "composite recording stopped";
          } else {
            const std::string path = args.out_dir + "/ripple_live_" +
                                     std::to_string(videos++) + ".mp4";
            status_line =
                composite_video.Open(path, args.fps, frame.size(), &error)
                    ? "recording " + path
                    : error;
          }
          break;
        case 'k':
          if (raw.is_open()) {
            status_line = "raw recording stopped (" +
                          std::to_string(raw.frames()) + " frames)";
            raw.Close();
          } else {
            const std::string dir =
                args.out_dir + "/ripple_raw_" + std::to_string(raws++);
            status_line =
                raw.Open(dir, &error) ? "recording raw to " + dir : error;
          }
          break;
        case ' ':
          paused = !paused;
          break;
        case 'q':
        case 27:
          quit = true;
          break;
        default:
          break;
      }
      if (water_changed) {
        if (!pipeline->water().SetOptions(w, &error)) status_line = error;
      }
    }

    // Next frame; a camera that stops delivering is lost.
    if (!paused && !quit) {
      t_cap = Clock::now();
      cv::Mat next;
      fresh = cap.read(next) && !next.empty();
      if (!fresh) {
        if (++failures >= 30) {
          exit_code = kExitRuntime;
          exit_message =
              "camera '" + args.input + "' lost (no frame for 30 reads)";
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      } else if (next.size() != frame.size()) {
        exit_code = kExitRuntime;
        exit_message =
            "camera '" + args.input + "' changed its frame size mid-run";
        break;
      } else {
        frame = next;
        failures = 0;
      }
    }
  }
  // Recordings are finalized whatever ended the session.
  composite_video.Close();
  raw.Close();
  std::printf("%s", table.Format("live").c_str());
  if (exit_code != kExitOk) return Fail(exit_code, exit_message);
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
                  "Capture size WxH (default: the calibration's)");
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
