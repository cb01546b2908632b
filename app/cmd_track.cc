// `ripple track`: poses of the tank board and the pen, one CSV row per
// object per frame, optionally with a debug overlay video.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

#include "app/app_common.h"
#include "app/app_options.h"
#include "app/app_smoothing.h"
#include "app/app_source.h"
#include "app/app_video.h"
#include "app/command.h"
#include "tracking/pose_csv.h"
#include "tracking/tracker.h"

namespace ripple::app {
namespace {

namespace fs = std::filesystem;
using tracking::FrameResult;
using tracking::TrackStatus;

void DrawAxes(cv::Mat* image, const tracking::Camera& camera,
              const tracking::Pose& cam_from_object, double length,
              int thickness) {
  const Eigen::Vector3d o = cam_from_object * Eigen::Vector3d::Zero();
  if (o.z() <= 0.01) return;
  const Eigen::Vector2d po = camera.Project(o);
  const cv::Scalar colours[3] = {{0, 0, 255}, {0, 200, 0}, {255, 0, 0}};
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d p =
        cam_from_object * (length * Eigen::Vector3d::Unit(a));
    if (p.z() <= 0.01) continue;
    const Eigen::Vector2d pp = camera.Project(p);
    cv::line(*image, cv::Point2d(po.x(), po.y()), cv::Point2d(pp.x(), pp.y()),
             colours[a], thickness, cv::LINE_AA);
  }
}

void DrawOverlay(const tracking::Tracker& tracker, const FrameResult& r,
                 cv::Mat* image) {
  const tracking::Camera& camera = tracker.camera();
  const tracking::Rig& rig = tracker.rig();
  for (const tracking::TagDetection& d : r.detections) {
    std::vector<cv::Point> poly;
    for (const auto& c : d.corners)
      poly.emplace_back(int(std::lround(c.x())), int(std::lround(c.y())));
    const bool pen = rig.FindPenFace(d.id) != nullptr;
    cv::polylines(*image, poly, true,
                  pen ? cv::Scalar(255, 0, 255) : cv::Scalar(0, 255, 255), 1,
                  cv::LINE_AA);
    cv::circle(*image, poly[0], 3, cv::Scalar(0, 0, 255), -1);
    cv::putText(
        *image, std::to_string(d.id),
        cv::Point2d(
            0.25 * (d.corners[0] + d.corners[1] + d.corners[2] + d.corners[3])
                        .x() -
                6,
            0.25 * (d.corners[0] + d.corners[1] + d.corners[2] + d.corners[3])
                        .y() +
                5),
        cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 128, 255), 1,
        cv::LINE_AA);
  }
  if (r.tank.has_pose())
    DrawAxes(image, camera, *r.tank.cam_from_object, 0.05, 2);
  if (r.pen.has_pose()) {
    DrawAxes(image, camera, *r.pen.cam_from_object, 0.025, 2);
    const Eigen::Vector3d tip = *r.pen.cam_from_object * rig.pen->tip_in_pen;
    if (tip.z() > 0.01) {
      const Eigen::Vector2d p = camera.Project(tip);
      cv::circle(*image, cv::Point2d(p.x(), p.y()), 5, cv::Scalar(0, 255, 0), 2,
                 cv::LINE_AA);
    }
  }
  char text[160];
  std::snprintf(text, sizeof(text), "#%d tank %s (%.2f px)  pen %s  %.2f ms%s",
                r.frame, tracking::ToString(r.tank.status), r.tank.rmse_px,
                tracking::ToString(r.pen.status), r.timings.total_ms,
                r.cut ? "  CUT" : "");
  cv::putText(*image, text, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(*image, text, cv::Point(8, 18), cv::FONT_HERSHEY_SIMPLEX, 0.5,
              cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
}

struct TrackArgs {
  std::string input, out, overlay;
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  double fps = 0;
  int max_frames = 0;
  double decimate = tracking::TagDetectorOptions{}.quad_decimate;
  int threads = 1;
  std::string pen_mode = "joint";
  std::string face_selection = "uncertainty";
  bool no_refine = false, no_roi = false, no_dense = false, no_shaft = false;
  SmoothingArgs smoothing;
  double tank_hold_s = tracking::TrackerOptions{}.tank_hold_s;
  double pen_hold_s = tracking::TrackerOptions{}.pen_hold_s;
};

int RunTrack(const TrackArgs& args) {
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  tracking::TrackerOptions options;
  options.detector.quad_decimate = args.decimate;
  options.detector.threads = args.threads;
  // Frames are decoded as the camera file says they encode light.
  options.detector.transfer = camera->transfer;
  options.pen_mode = *tracking::ParsePenMode(args.pen_mode);
  options.face_selection = *tracking::ParseFaceSelection(args.face_selection);
  options.pose.refine = !args.no_refine;
  options.pen_dense.enabled = !args.no_dense;
  options.pen_shaft.enabled = !args.no_shaft;
  options.roi.enabled = !args.no_roi;
  options.tank_hold_s = args.tank_hold_s;
  options.pen_hold_s = args.pen_hold_s;
  std::string error;
  if (!ApplySmoothingOptions(args.smoothing, &options.smoothing, &error))
    return Fail(kExitBadInput, error);
  if (!options.IsValid(&error)) return Fail(kExitBadInput, error);

  const double fps = args.fps > 0 ? args.fps : 30.0;
  auto source = FrameSource::Open(args.input, &error, fps);
  if (!source) return Fail(kExitBadInput, error);

  cv::Mat image;
  double time_s = 0;
  int code = 0;
  if (!ReadFirstFrame(source.get(), &image, &time_s, &code, &error))
    return Fail(code, error);
  if (!MatchCameraToFrames(image.size(), args.camera, &*camera, &error))
    return Fail(kExitBadInput, error);

  tracking::PoseCsvWriter csv;
  if (!csv.Open(args.out, &error)) return Fail(kExitBadInput, error);
  VideoOut overlay;
  if (!args.overlay.empty() &&
      !overlay.Open(args.overlay, fps, image.size(), &error))
    return Fail(kExitBadInput, error);

  tracking::Tracker tracker(*camera, *rig, options);
  int frames = 0, tank_tracked = 0, pen_tracked = 0, tank_any = 0;
  std::vector<double> ms;
  do {
    if (image.cols != camera->width || image.rows != camera->height)
      return Fail(kExitRuntime, "frame " + std::to_string(frames) + " of '" +
                                    args.input + "' changed size mid-stream");
    const FrameResult r = tracker.Track(image, time_s);
    for (const tracking::PoseRow& row : tracker.ToPoseRows(r)) {
      if (!csv.Write(row))
        return Fail(kExitRuntime, "cannot write '" + args.out + "'");
    }
    tank_tracked += r.tank.status == TrackStatus::kTracked;
    tank_any += r.tank.has_pose();
    pen_tracked += r.pen.status == TrackStatus::kTracked;
    ms.push_back(r.timings.total_ms);
    if (overlay.is_open()) {
      DrawOverlay(tracker, r, &image);
      overlay.Write(image);
    }
    ++frames;
    if (args.max_frames > 0 && frames >= args.max_frames) break;
  } while (source->Read(&image, &time_s));
  std::string overlay_error;
  const bool overlay_ok = overlay.Close(&overlay_error);
  if (!csv.Close())
    return Fail(kExitRuntime, "cannot finish '" + args.out + "'");
  if (!overlay_ok) return Fail(kExitRuntime, overlay_error);
  if (!source->error().empty())
    return Fail(kExitRuntime, source->error() + " (poses written for " +
                                  std::to_string(frames) + " frames)");
  std::sort(ms.begin(), ms.end());
  std::printf(
      "track: %d frames, tank tracked %d (%.0f%%), pen tracked %d (%.0f%%), "
      "%.2f ms/frame median -> %s\n",
      frames, tank_tracked, 100.0 * tank_tracked / frames, pen_tracked,
      100.0 * pen_tracked / frames, ms[ms.size() / 2], args.out.c_str());
  if (tank_any == 0)
    return Fail(kExitRuntime,
                "the tank board was never found in '" + args.input + "'");
  return kExitOk;
}

CommandAction SetupTrack(CLI::App* sub) {
  auto args = std::make_shared<TrackArgs>();
  sub->add_option("--input", args->input,
                  "Image folder, video file or camera (index or /dev path)")
      ->required();
  sub->add_option("--out", args->out, "Pose CSV to write")->required();
  sub->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--overlay", args->overlay,
                  "Debug video: corners, ids, axes, tip (.mp4, .mkv, .avi)");
  sub->add_option("--fps", args->fps,
                  "Frame rate of an image folder and of the overlay video "
                  "(videos use their own timestamps; default 30)")
      ->check(CLI::PositiveNumber);
  sub->add_option("--max-frames", args->max_frames, "Stop after N frames")
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--decimate", args->decimate,
                  "libapriltag quad_decimate (1 = full resolution)")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 8.0));
  sub->add_option("--threads", args->threads, "Detector threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  sub->add_option("--pen-mode", args->pen_mode, "joint or best-face")
      ->capture_default_str()
      ->check(CLI::IsMember({"joint", "best-face"}));
  sub->add_option("--face-selection", args->face_selection,
                  "best-face rule: uncertainty (least tip uncertainty) or "
                  "frontal (the paper's)")
      ->capture_default_str()
      ->check(CLI::IsMember({"uncertainty", "frontal"}));
  sub->add_flag("--no-refine", args->no_refine, "Skip the Ceres refinement");
  sub->add_flag("--no-roi", args->no_roi, "Search the full frame every time");
  sub->add_flag("--no-dense", args->no_dense,
                "Skip the pen's dense photometric refinement");
  sub->add_flag("--no-shaft", args->no_shaft,
                "Skip the refinement of the pen by its shaft's edges");
  AddSmoothingOptions(sub, &args->smoothing);
  sub->add_option("--hold", args->tank_hold_s,
                  "Seconds an occluded board stays 'held'")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  sub->add_option("--pen-hold", args->pen_hold_s,
                  "Seconds a vanished pen stays 'held'")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  return [args] { return RunTrack(*args); };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(track, "Track the board and the pen into a pose CSV",
                        SetupTrack);

}  // namespace ripple::app
