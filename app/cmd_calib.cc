// `ripple calib camera|rig|pen|check`: calibration of a real set-up, in the
// order of DESIGN.md (camera, then the cube/board layout, then the pen tip,
// then a check of the whole). Results are written only on success, through
// a temporary file (calib/calib_io.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "app/app_common.h"
#include "app/app_source.h"
#include "app/app_wxh.h"
#include "app/command.h"
#include "calib/calib_io.h"
#include "calib/camera_calib.h"
#include "calib/pivot_calib.h"
#include "calib/rig_calib.h"
#include "calib/tip_check.h"
#include "tracking/object_pose.h"
#include "tracking/tag_detector.h"
#include "tracking/tag_family.h"

namespace ripple::app {
namespace {

using tracking::Pose;

struct CalibArgs {
  std::string input;
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string out;
  int every = 1;  // use every n-th frame
  // camera
  std::string chessboard;
  double square = 0.025;
  std::string target;
  int min_views = -1;  // -1: the command's default
  double max_edge_width = 3.5;
  std::string distortion = "auto";
  bool k3 = false;        // --k3: --distortion k1k2k3
  bool rational = false;  // --rational: --distortion rational
  // rig
  std::string object = "auto";
  int reference = -1;
  bool free_tags = false;
  // pen
  std::string frame = "auto";
  double min_spread_deg = 8.0;
  // check
  double still_radius_mm = 4.0;
  double min_still_s = 0.4;
};

// The parent folder of an output file must exist before the work starts.
bool CheckOutputPath(const std::string& path, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) parent = ".";
  if (path.empty() || fs::is_directory(path, ec) ||
      !fs::is_directory(parent, ec)) {
    *error = "--out '" + path + "': not a file in an existing folder";
    return false;
  }
  return true;
}

// Reads every `every`-th frame; calls fn(bgr, gray, time, index). Returns
// kExitOk, or the exit code after reporting a failure.
int ForEachFrame(
    const CalibArgs& args,
    const std::function<void(const cv::Mat&, const cv::Mat&, double, int)>& fn,
    const cv::Size& expected_size = cv::Size()) {
  std::string error;
  auto source = FrameSource::Open(args.input, &error);
  if (!source) return Fail(kExitBadInput, error);
  cv::Mat bgr, gray;
  double t = 0;
  int index = 0;
  while (source->Read(&bgr, &t)) {
    if (index == 0 && expected_size.area() > 0 && bgr.size() != expected_size)
      return Fail(kExitBadInput, "--camera is for " +
                                     std::to_string(expected_size.width) + "x" +
                                     std::to_string(expected_size.height) +
                                     " images but '" + args.input + "' has " +
                                     std::to_string(bgr.cols) + "x" +
                                     std::to_string(bgr.rows));
    if (index % args.every == 0) {
      cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
      fn(bgr, gray, t, index);
    }
    ++index;
    if (index % 50 == 0) std::fprintf(stderr, "\rcalib: %d frames", index);
  }
  if (index >= 50) std::fprintf(stderr, "\n");
  if (!source->error().empty()) return Fail(kExitRuntime, source->error());
  if (index == 0)
    return Fail(kExitBadInput, "no frames in '" + args.input + "'");
  return kExitOk;
}

tracking::TagDetector MakeDetector(const std::string& family) {
  tracking::TagDetectorOptions options;
  options.family = family;
  options.quad_decimate = 1.0;  // calibration: find small tags too
  return tracking::TagDetector(options);
}

// ---------------------------------------------------------------- camera

int RunCalibCamera(const CalibArgs& args) {
  std::string error;
  if (!CheckOutputPath(args.out, &error)) return Fail(kExitBadInput, error);
  if (!args.chessboard.empty() && !args.target.empty())
    return Fail(kExitBadInput,
                "give either --chessboard or --target, not both");
  calib::DistortionModel distortion =
      *calib::ParseDistortionModel(args.distortion);  // checked by CLI11
  if (args.k3 || args.rational) {
    if (distortion != calib::DistortionModel::kAuto ||
        (args.k3 && args.rational))
      return Fail(kExitBadInput,
                  "give one of --distortion, --k3 and --rational");
    distortion = args.k3 ? calib::DistortionModel::kK1K2K3
                         : calib::DistortionModel::kRational;
  }
  int cols = 9, rows = 6;
  std::optional<tracking::Rig> target;
  std::unique_ptr<tracking::TagDetector> detector;
  int border_cells = 8;
  if (!args.target.empty()) {
    target = LoadRigOrReport(args.target);
    if (!target) return kExitBadInput;
    if (!calib::IsPlanarTarget(target->tank_tags))
      return Fail(kExitBadInput, "--target '" + args.target +
                                     "': its board tags are not all in the "
                                     "plane z = 0");
    detector =
        std::make_unique<tracking::TagDetector>(MakeDetector(target->family));
    border_cells =
        tracking::TagFamily::Create(target->family)->width_at_border();
  } else if (!args.chessboard.empty()) {
    WxH pattern;
    ParseWxH(args.chessboard, &pattern, WxHLimits::Pattern());  // validated
    cols = pattern.width;
    rows = pattern.height;
  }
  calib::ViewSelectionOptions select;
  select.max_edge_width_px = args.max_edge_width;
  std::unique_ptr<calib::ViewSelector> selector;
  int found = 0, frames = 0;
  cv::Size size;
  const int code = ForEachFrame(
      args, [&](const cv::Mat& bgr, const cv::Mat& gray, double, int index) {
        ++frames;
        if (!selector) {
          size = gray.size();
          selector = std::make_unique<calib::ViewSelector>(select, size.width,
                                                           size.height);
        }
        calib::CalibView view;
        const bool ok = target ? calib::TagTargetView(gray, target->tank_tags,
                                                      detector->Detect(gray),
                                                      border_cells, 2, &view)
                               : calib::DetectChessboardView(
                                     gray, cols, rows, args.square, &view);
        if (!ok) return;
        ++found;
        view.frame = index;
        selector->Offer(std::move(view));
      });
  if (code != kExitOk) return code;
  if (found == 0)
    return Fail(kExitRuntime,
                "no target found in " + std::to_string(frames) +
                    " frames of '" + args.input + "' (" +
                    (target ? "tags of '" + args.target + "'"
                            : "a " + std::to_string(cols) + "x" +
                                  std::to_string(rows) + " chessboard") +
                    ")");
  std::printf(
      "camera: target in %d of %d frames; rejected %d blurred, %d "
      "duplicate views\n",
      found, frames, selector->blurred(), selector->duplicates());
  calib::CameraCalibOptions options;
  if (args.min_views > 0) options.min_views = args.min_views;
  options.max_views = std::max(options.max_views, options.min_views);
  options.distortion = distortion;
  tracking::Camera camera;
  calib::CameraCalibSummary summary;
  if (!calib::CalibrateCamera(options, selector->accepted(), size.width,
                              size.height, &camera, &summary, &error))
    return Fail(kExitRuntime, error);
  std::printf("%s", summary.BriefReport().c_str());
  std::printf(
      "fx %.2f fy %.2f cx %.2f cy %.2f; k1 %.4f k2 %.4f p1 %.5f p2 "
      "%.5f k3 %.4f",
      camera.fx, camera.fy, camera.cx, camera.cy, camera.dist[0],
      camera.dist[1], camera.dist[2], camera.dist[3], camera.dist[4]);
  if (summary.model == calib::DistortionModel::kRational)
    std::printf(" k4 %.4f k5 %.4f k6 %.4f", camera.dist[5], camera.dist[6],
                camera.dist[7]);
  std::printf("\n");
  if (summary.grid_coverage < 0.5)
    std::printf(
        "warning: the views cover only %.0f %% of the image; move the "
        "target into the corners for a better lens model\n",
        100 * summary.grid_coverage);
  // The file says how its model was chosen; the report's lines, minus the
  // trailing newline, become its comment.
  char head[96];
  std::snprintf(head, sizeof(head),
                "ripple calib camera: %d views, RMS %.3f px\n", summary.views,
                summary.rms_px);
  std::string comment = head + summary.ModelReport();
  comment.pop_back();
  if (!calib::SaveCameraAtomically(camera, args.out, &error, comment))
    return Fail(kExitRuntime, error);
  std::printf("camera -> %s\n", args.out.c_str());
  return kExitOk;
}

// ---------------------------------------------------------------- rig

struct Loaded {
  tracking::Camera camera;
  tracking::Rig rig;
};

int LoadInputs(const CalibArgs& args, Loaded* loaded) {
  auto camera = LoadCameraOrReport(args.camera);
  if (!camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  loaded->camera = *camera;
  loaded->rig = *rig;
  return kExitOk;
}

int RunCalibRig(const CalibArgs& args) {
  std::string error;
  if (!CheckOutputPath(args.out, &error)) return Fail(kExitBadInput, error);
  Loaded in;
  if (int code = LoadInputs(args, &in)) return code;
  if (args.object == "pen" && !in.rig.pen)
    return Fail(kExitBadInput, "--rig '" + args.rig + "' has no pen");
  tracking::TagDetector detector = MakeDetector(in.rig.family);
  std::vector<std::vector<tracking::TagDetection>> detections;
  const int code = ForEachFrame(
      args,
      [&](const cv::Mat&, const cv::Mat& gray, double, int) {
        detections.push_back(detector.Detect(gray));
      },
      cv::Size(in.camera.width, in.camera.height));
  if (code != kExitOk) return code;
  std::string object = args.object;
  if (object == "auto")
    object = calib::ChooseLayoutObject(in.rig, detections) ==
                     calib::LayoutObject::kPen
                 ? "pen"
                 : "tank";
  std::vector<tracking::TagPlacement>& tags =
      object == "pen" ? in.rig.pen->faces : in.rig.tank_tags;
  calib::RigCalibOptions options;
  options.reference_id = args.reference;
  options.in_plane_only = object == "tank" && !args.free_tags;
  if (args.min_views > 0) options.min_views = args.min_views;
  std::vector<tracking::TagPlacement> refined;
  calib::RigCalibSummary summary;
  if (!calib::CalibrateTagLayout(options, in.camera, tags, detections, &refined,
                                 &summary, &error))
    return Fail(kExitRuntime, object + " layout: " + error);
  std::printf("rig (%s): %s", object.c_str(), summary.BriefReport().c_str());
  tags = refined;
  if (!calib::SaveRigAtomically(in.rig, args.out, &error))
    return Fail(kExitRuntime, error);
  std::printf("rig -> %s\n", args.out.c_str());
  return kExitOk;
}

// ---------------------------------------------------------------- pen

std::optional<Pose> ObjectPoseOf(
    const tracking::Camera& camera,
    const std::vector<tracking::TagPlacement>& tags,
    const std::vector<tracking::TagDetection>& d, double max_rmse_px) {
  const auto obs = tracking::MatchObservations(camera, tags, d);
  if (obs.empty()) return std::nullopt;
  tracking::ObjectPose pose;
  if (!tracking::EstimateObjectPose(tracking::PoseEstimatorOptions(), camera,
                                    obs, {}, &pose) ||
      pose.rmse_px > max_rmse_px)
    return std::nullopt;
  return pose.cam_from_object;
}

int RunCalibPen(const CalibArgs& args) {
  std::string error;
  if (!CheckOutputPath(args.out, &error)) return Fail(kExitBadInput, error);
  Loaded in;
  if (int code = LoadInputs(args, &in)) return code;
  if (!in.rig.pen)
    return Fail(kExitBadInput, "--rig '" + args.rig + "' has no pen");
  tracking::TagDetector detector = MakeDetector(in.rig.family);
  std::vector<Pose> cam_from_pen, tank_from_pen;
  int frames = 0;
  const int code = ForEachFrame(
      args,
      [&](const cv::Mat&, const cv::Mat& gray, double, int) {
        ++frames;
        const auto d = detector.Detect(gray);
        const auto pen = ObjectPoseOf(in.camera, in.rig.pen->faces, d, 2.0);
        if (!pen) return;
        cam_from_pen.push_back(*pen);
        const auto tank = ObjectPoseOf(in.camera, in.rig.tank_tags, d, 2.0);
        if (tank) tank_from_pen.push_back(tank->Inverse() * *pen);
      },
      cv::Size(in.camera.width, in.camera.height));
  if (code != kExitOk) return code;
  if (cam_from_pen.empty())
    return Fail(kExitRuntime, "no target found: the pen cube was not seen in " +
                                  std::to_string(frames) + " frames of '" +
                                  args.input + "'");
  std::string frame = args.frame;
  if (frame == "auto")
    frame =
        tank_from_pen.size() >= 0.8 * cam_from_pen.size() ? "tank" : "camera";
  if (frame == "tank" && tank_from_pen.empty())
    return Fail(kExitRuntime, "--frame tank: the board was never seen");
  calib::PivotOptions options;
  if (args.min_views > 0) options.min_views = args.min_views;
  options.min_spread_rad = args.min_spread_deg * M_PI / 180.0;
  calib::PivotSummary summary;
  if (!calib::CalibratePivot(options,
                             frame == "tank" ? tank_from_pen : cam_from_pen,
                             &summary, &error))
    return Fail(kExitRuntime, "pen pivot: " + error);
  std::printf("%s", summary.BriefReport().c_str());
  std::printf("pivot point in the %s frame; tip moved %.2f mm from the rig's\n",
              frame.c_str(),
              1e3 * (summary.tip_in_pen - in.rig.pen->tip_in_pen).norm());
  in.rig.pen->tip_in_pen = summary.tip_in_pen;
  if (!calib::SaveRigAtomically(in.rig, args.out, &error))
    return Fail(kExitRuntime, error);
  std::printf("rig -> %s\n", args.out.c_str());
  return kExitOk;
}

// ---------------------------------------------------------------- check

int RunCalibCheck(const CalibArgs& args) {
  std::string error;
  if (!args.out.empty() && !CheckOutputPath(args.out, &error))
    return Fail(kExitBadInput, error);
  Loaded in;
  if (int code = LoadInputs(args, &in)) return code;
  if (!in.rig.pen)
    return Fail(kExitBadInput, "--rig '" + args.rig + "' has no pen");
  const auto points = calib::BoardCheckPoints(in.rig);
  if (points.empty())
    return Fail(kExitBadInput, "the board of '" + args.rig +
                                   "' has no printable check points");
  tracking::TagDetector detector = MakeDetector(in.rig.family);
  std::vector<calib::TipSample> samples;
  int frames = 0;
  const int code = ForEachFrame(
      args,
      [&](const cv::Mat&, const cv::Mat& gray, double t, int) {
        ++frames;
        const auto d = detector.Detect(gray);
        const auto pen = ObjectPoseOf(in.camera, in.rig.pen->faces, d, 2.0);
        const auto tank = ObjectPoseOf(in.camera, in.rig.tank_tags, d, 2.0);
        if (!pen || !tank) return;
        samples.push_back(
            {t, tank->Inverse() * (*pen * in.rig.pen->tip_in_pen)});
      },
      cv::Size(in.camera.width, in.camera.height));
  if (code != kExitOk) return code;
  if (samples.empty())
    return Fail(kExitRuntime,
                "no target found: the board and the pen were never seen "
                "together in " +
                    std::to_string(frames) + " frames of '" + args.input + "'");
  calib::TipCheckOptions options;
  options.still_radius_m = 1e-3 * args.still_radius_mm;
  options.min_still_s = args.min_still_s;
  calib::TipCheckSummary summary;
  if (!calib::EvaluateTipCheck(options, points, samples, &summary, &error))
    return Fail(kExitRuntime, error);
  std::printf(
      "check: %zu of %zu points touched (tip tracked in %zu of %d "
      "frames)\n%s",
      summary.touches.size(), points.size(), samples.size(), frames,
      summary.BriefReport().c_str());
  if (!args.out.empty()) {
    if (!calib::WriteTipCheckCsv(summary, args.out, &error))
      return Fail(kExitRuntime, error);
    std::printf("check -> %s\n", args.out.c_str());
  }
  return kExitOk;
}

// ---------------------------------------------------------------- CLI

void AddInput(CLI::App* app, CalibArgs* args) {
  app->add_option("--input", args->input,
                  "Video file, image folder, or camera index/device")
      ->required();
  app->add_option("--every", args->every, "Use every n-th frame")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
}

void AddCameraRig(CLI::App* app, CalibArgs* args) {
  app->add_option("--camera", args->camera, "Camera calibration YAML")
      ->capture_default_str();
  app->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
}

CommandAction SetupCalib(CLI::App* sub) {
  auto args = std::make_shared<CalibArgs>();
  sub->require_subcommand(1);

  CLI::App* camera = sub->add_subcommand(
      "camera",
      "Intrinsics and distortion from views of a chessboard or a "
      "flat tag board");
  AddInput(camera, args.get());
  camera
      ->add_option("--chessboard", args->chessboard,
                   "Chessboard inner corners COLSxROWS (default 9x6)")
      ->check(WxHValidator(WxHLimits::Pattern()));
  camera->add_option("--square", args->square, "Chessboard square, metres")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  camera->add_option("--target", args->target,
                     "Rig YAML whose (flat) tank board is the target");
  camera->add_option("--out", args->out, "Camera YAML to write")->required();
  camera->add_option("--min-views", args->min_views,
                     "Fewest sharp, distinct views (default 10)");
  camera
      ->add_option("--max-edge-width", args->max_edge_width,
                   "Reject views whose edges are blurrier (10-90 % rise, "
                   "pixels)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  camera
      ->add_option("--distortion", args->distortion,
                   "Lens distortion model: auto (chosen by cross-validation "
                   "over views), k1k2 (k1 k2 p1 p2), k1k2k3 (and k3), "
                   "rational (k1..k6 p1 p2)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "k1k2", "k1k2k3", "rational"}));
  camera->add_flag("--k3", args->k3, "The same as --distortion k1k2k3");
  camera->add_flag("--rational", args->rational,
                   "The same as --distortion rational");

  CLI::App* rig = sub->add_subcommand(
      "rig", "Bundle adjustment of the cube faces or board tags");
  AddInput(rig, args.get());
  AddCameraRig(rig, args.get());
  rig->add_option("--out", args->out, "Refined rig YAML")->required();
  rig->add_option("--object", args->object,
                  "Which layout: pen, tank, or auto (the one seen more)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "pen", "tank"}));
  rig->add_option("--reference", args->reference,
                  "Tag held fixed (default: the one seen most)");
  rig->add_flag("--free-tags", args->free_tags,
                "Board tags: refine all 6 degrees of freedom (default: in "
                "the board plane only)");
  rig->add_option("--min-views", args->min_views,
                  "Fewest views with >= 2 tags (default 10)");

  CLI::App* pen = sub->add_subcommand(
      "pen", "Pivot calibration of the pen tip (tip held in a dimple)");
  AddInput(pen, args.get());
  AddCameraRig(pen, args.get());
  pen->add_option("--out", args->out, "Rig YAML with the new tip")->required();
  pen->add_option("--frame", args->frame,
                  "Pivot fixed in: camera (still camera), tank (board in "
                  "view), auto")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "camera", "tank"}));
  pen->add_option("--min-views", args->min_views,
                  "Fewest tracked frames (default 15)");
  pen->add_option("--min-spread-deg", args->min_spread_deg,
                  "Least rotation spread about two axes, degrees")
      ->capture_default_str();

  CLI::App* check = sub->add_subcommand(
      "check", "Touch the printed points with the tip: error per point");
  AddInput(check, args.get());
  AddCameraRig(check, args.get());
  check->add_option("--out", args->out, "Optional CSV report");
  check
      ->add_option("--still-radius-mm", args->still_radius_mm,
                   "A touch stays within this radius, mm")
      ->capture_default_str();
  check
      ->add_option("--min-still-s", args->min_still_s,
                   "A touch lasts at least this long, seconds")
      ->capture_default_str();

  return [args, camera, rig, pen, check] {
    if (camera->parsed()) return RunCalibCamera(*args);
    if (rig->parsed()) return RunCalibRig(*args);
    if (pen->parsed()) return RunCalibPen(*args);
    if (check->parsed()) return RunCalibCheck(*args);
    return Fail(kExitBadInput, "calib: give camera, rig, pen or check");
  };
}

}  // namespace

RIPPLE_REGISTER_COMMAND(calib,
                        "Calibrate: camera intrinsics, rig layout, pen tip, "
                        "tip check",
                        SetupCalib);

}  // namespace ripple::app
