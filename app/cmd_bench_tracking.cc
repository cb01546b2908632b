// `ripple bench tracking`: run time against error of the tracker's settings
// and of three baselines on synth's benchmark preset, rendered in memory.
//
// Frames are rendered once and every setting runs on each frame in turn.
// Settings without region search share one full-frame detection per
// decimation (timed once per frame and charged to each of them); settings
// with region search detect on their own. The baselines get the corrected
// corners of the default decimation's detection and are charged its time.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "app/app_bench.h"
#include "app/app_common.h"
#include "app/command.h"
#include "tracking/baselines.h"
#include "tracking/synth/synth.h"
#include "tracking/tracker.h"

namespace ripple::app {
namespace {

using tracking::Pose;
constexpr double kDeg = M_PI / 180.0;

double NowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(v.size() - 1, size_t(p * (v.size() - 1) + 0.5));
  return v[i];
}

enum class Baseline { kNone, kPaper, kIppe, kSqpnpLm };

struct Setting {
  std::string name;
  Baseline baseline = Baseline::kNone;
  tracking::TrackerOptions options;
  std::unique_ptr<tracking::Tracker> tracker;
  // Accumulated per frame.
  std::vector<double> ms, tank_rot, tank_mm, pen_rot, pen_mm, tip_mm;
  int flips = 0, tank_tracked = 0, tank_visible = 0, pen_tracked = 0,
      pen_visible = 0;
};

struct Outcome {
  std::optional<Pose> tank, pen;
  bool tank_tracked = false, pen_tracked = false;
  double ms = 0;
  std::string pen_tags;  // faces used, '+'-separated (settings only)
  bool pen_flip_rejected = false, pen_jumped = false, pen_ambiguous = false;
};

// Per-frame errors of one setting (the --frames-csv rows).
struct FrameErrors {
  double tank_rot_deg = NAN, pen_rot_deg = NAN, tip_mm = NAN;
  bool flip = false;
};

std::string SettingName(const tracking::TrackerOptions& o) {
  char buf[112];
  std::snprintf(
      buf, sizeof(buf), "d%g %s%s%s %s%s", o.detector.quad_decimate,
      o.pen_mode == tracking::PenMode::kJoint ? "joint" : "best-face",
      o.pen_mode == tracking::PenMode::kBestFace &&
              o.face_selection == tracking::FaceSelection::kMostFrontal
          ? "(frontal)"
          : "",
      o.pose.refine ? " ceres" : " ippe", o.roi.enabled ? "roi" : "full",
      o.pen_dense.enabled ? " dense" : "");
  return buf;
}

std::vector<std::unique_ptr<Setting>> MakeSettings(const std::string& sweep,
                                                   int threads) {
  const tracking::TrackerOptions defaults;
  std::vector<tracking::TrackerOptions> list;
  if (sweep == "full") {
    for (double d : {1.0, 1.5, 2.0, 3.0})
      for (bool refine : {true, false})
        for (auto mode :
             {tracking::PenMode::kJoint, tracking::PenMode::kBestFace})
          for (bool roi : {true, false}) {
            tracking::TrackerOptions o = defaults;
            o.detector.quad_decimate = d;
            o.pose.refine = refine;
            o.pen_mode = mode;
            o.roi.enabled = roi;
            list.push_back(o);
          }
  } else if (sweep == "default") {
    list.push_back(defaults);
  } else {
    list.push_back(defaults);
    for (double d : {1.0, 1.5, 2.0, 3.0}) {
      if (d == defaults.detector.quad_decimate) continue;
      tracking::TrackerOptions o = defaults;
      o.detector.quad_decimate = d;
      list.push_back(o);
    }
    tracking::TrackerOptions o = defaults;
    o.pose.refine = !defaults.pose.refine;
    list.push_back(o);
    o = defaults;
    o.pen_mode = tracking::PenMode::kBestFace;
    list.push_back(o);
    o = defaults;
    o.roi.enabled = !defaults.roi.enabled;
    list.push_back(o);
    o = defaults;
    o.pen_dense.enabled = !defaults.pen_dense.enabled;
    list.push_back(o);
  }
  if (sweep != "default") {
    tracking::TrackerOptions frontal = defaults;
    frontal.pen_mode = tracking::PenMode::kBestFace;
    frontal.face_selection = tracking::FaceSelection::kMostFrontal;
    list.push_back(frontal);
  }
  std::vector<std::unique_ptr<Setting>> settings;
  for (tracking::TrackerOptions& o : list) {
    o.detector.threads = threads;
    auto s = std::make_unique<Setting>();
    s->options = o;
    s->name = SettingName(o);
    if (o.detector.quad_decimate == defaults.detector.quad_decimate &&
        o.pen_mode == defaults.pen_mode &&
        o.pose.refine == defaults.pose.refine &&
        o.roi.enabled == defaults.roi.enabled &&
        o.pen_dense.enabled == defaults.pen_dense.enabled &&
        o.face_selection == defaults.face_selection)
      s->name += " [default]";
    settings.push_back(std::move(s));
  }
  if (sweep == "default") return settings;
  for (auto [b, name] :
       {std::make_pair(Baseline::kPaper,
                       "paper: frontal face, estimate_tag_pose"),
        std::make_pair(Baseline::kIppe, "opencv IPPE_SQUARE, best-posed face"),
        std::make_pair(Baseline::kSqpnpLm, "opencv SQPNP+LM, all corners")}) {
    auto s = std::make_unique<Setting>();
    s->baseline = b;
    s->name = name;
    settings.push_back(std::move(s));
  }
  return settings;
}

Outcome RunBaseline(Baseline b, const tracking::Camera& camera,
                    const tracking::Rig& rig,
                    const std::vector<tracking::TagDetection>& dets) {
  Outcome o;
  const double t0 = NowMs();
  auto pose = [&](const std::vector<tracking::TagPlacement>& tags,
                  const Eigen::Vector3d& point) -> std::optional<Pose> {
    const auto obs = tracking::MatchObservations(camera, tags, dets);
    if (obs.empty()) return std::nullopt;
    switch (b) {
      case Baseline::kPaper:
        return tracking::PaperFrontalTagPose(camera, obs);
      case Baseline::kIppe:
        return tracking::OpenCvIppeBestTagPose(camera, obs, point);
      case Baseline::kSqpnpLm:
        return tracking::SqpnpLmPose(camera, obs);
      default:
        return std::nullopt;
    }
  };
  o.tank = pose(rig.tank_tags, Eigen::Vector3d::Zero());
  if (rig.pen) o.pen = pose(rig.pen->faces, rig.pen->tip_in_pen);
  o.tank_tracked = o.tank.has_value();
  o.pen_tracked = o.pen.has_value();
  o.ms = NowMs() - t0;
  return o;
}

FrameErrors Accumulate(const tracking::Rig& rig, const synth::FrameSpec& spec,
                       const synth::RenderedFrame& frame, const Outcome& o,
                       Setting* s) {
  FrameErrors fe;
  s->ms.push_back(o.ms);
  const bool tank_visible = !frame.tank_tags.empty();
  const bool pen_visible = !frame.pen_tags.empty();
  s->tank_visible += tank_visible;
  s->pen_visible += pen_visible;
  s->tank_tracked += tank_visible && o.tank_tracked;
  s->pen_tracked += pen_visible && o.pen_tracked;
  bool flip = false;
  if (o.tank) {
    const double r =
        tracking::RotationDistance(*o.tank, spec.scene.cam_from_tank);
    s->tank_rot.push_back(r / kDeg);
    fe.tank_rot_deg = r / kDeg;
    s->tank_mm.push_back(1000 * tracking::TranslationDistance(
                                    *o.tank, spec.scene.cam_from_tank));
    flip |= r > 10 * kDeg;
  }
  if (o.pen && spec.scene.tank_from_pen) {
    const Pose truth = spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
    const double r = tracking::RotationDistance(*o.pen, truth);
    s->pen_rot.push_back(r / kDeg);
    fe.pen_rot_deg = r / kDeg;
    s->pen_mm.push_back(1000 * tracking::TranslationDistance(*o.pen, truth));
    flip |= r > 10 * kDeg;
    if (o.tank) {
      const Eigen::Vector3d tip =
          o.tank->Inverse() * (*o.pen * rig.pen->tip_in_pen);
      const Eigen::Vector3d true_tip =
          *spec.scene.tank_from_pen * rig.pen->tip_in_pen;
      s->tip_mm.push_back(1000 * (tip - true_tip).norm());
      fe.tip_mm = s->tip_mm.back();
    }
  }
  s->flips += flip;
  fe.flip = flip;
  return fe;
}

// Error against time, one point per setting (log-scaled axes).
void Plot(const std::vector<std::unique_ptr<Setting>>& settings,
          const std::string& title, const std::string& path) {
  const int w = 1100, h = 700, left = 70, right = 430, top = 40, bottom = 60;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = 1e9, x1 = 0, y0 = 1e9, y1 = 0;
  for (const auto& s : settings) {
    const double x = Percentile(s->ms, 0.5), y = Percentile(s->tip_mm, 0.5);
    if (!(x > 0) || !(y > 0)) continue;
    x0 = std::min(x0, x), x1 = std::max(x1, x);
    y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  if (!(x1 > 0)) return;
  x0 = std::log10(x0) - 0.05, x1 = std::log10(x1) + 0.05;
  y0 = std::log10(y0) - 0.05, y1 = std::log10(y1) + 0.05;
  auto px = [&](double x, double y) {
    return cv::Point(
        int(left + (std::log10(x) - x0) / (x1 - x0) * (w - left - right)),
        int(h - bottom -
            (std::log10(y) - y0) / (y1 - y0) * (h - top - bottom)));
  };
  cv::rectangle(img, cv::Point(left, top), cv::Point(w - right, h - bottom),
                cv::Scalar(0, 0, 0));
  for (int e = int(std::floor(x0)); e <= int(std::ceil(x1)); ++e)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (std::log10(v) < x0 || std::log10(v) > x1) continue;
      const cv::Point p = px(v, std::pow(10.0, y0));
      cv::line(img, p, cv::Point(p.x, top), cv::Scalar(220, 220, 220));
      std::ostringstream t;
      t << v;
      cv::putText(img, t.str(), p + cv::Point(-8, 18), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(0, 0, 0));
    }
  for (int e = int(std::floor(y0)); e <= int(std::ceil(y1)); ++e)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (std::log10(v) < y0 || std::log10(v) > y1) continue;
      const cv::Point p = px(std::pow(10.0, x0), v);
      cv::line(img, p, cv::Point(w - right, p.y), cv::Scalar(220, 220, 220));
      std::ostringstream t;
      t << v;
      cv::putText(img, t.str(), p + cv::Point(-40, 4), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(0, 0, 0));
    }
  cv::putText(img, title, cv::Point(left, 25), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "ms per frame (median, log)", cv::Point(left + 200, h - 20),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::putText(img, "tip error mm (median, log)", cv::Point(5, top - 8),
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  int row = 0;
  for (size_t i = 0; i < settings.size(); ++i) {
    const Setting& s = *settings[i];
    const double x = Percentile(s.ms, 0.5), y = Percentile(s.tip_mm, 0.5);
    const cv::Scalar colour =
        s.baseline != Baseline::kNone
            ? cv::Scalar(0, 0, 220)
            : (s.name.find("[default]") != std::string::npos
                   ? cv::Scalar(0, 160, 0)
                   : cv::Scalar(200, 80, 0));
    const std::string label = std::to_string(i + 1);
    if (x > 0 && y > 0) {
      cv::circle(img, px(x, y), 4, colour, -1, cv::LINE_AA);
      cv::putText(img, label, px(x, y) + cv::Point(5, -4),
                  cv::FONT_HERSHEY_SIMPLEX, 0.35, colour, 1, cv::LINE_AA);
    }
    cv::putText(img, label + ": " + s.name,
                cv::Point(w - right + 10, top + 12 + 16 * row++),
                cv::FONT_HERSHEY_SIMPLEX, 0.38, colour, 1, cv::LINE_AA);
  }
  cv::imwrite(path, img);
}

struct BenchArgs {
  std::string camera = DefaultCameraPath();
  std::string rig = DefaultRigPath();
  std::string out = "bench_tracking";
  std::vector<std::string> sizes = {"640x480", "1280x720"};
  std::string sweep = "short";
  int frames = 500;
  int first = 0;  // frames before this are not rendered or tracked
  bool frames_csv = false;
  int threads = 1;
  uint64_t seed = 1;
};

int RunBenchTracking(const BenchArgs& args) {
  auto base_camera = LoadCameraOrReport(args.camera);
  if (!base_camera) return kExitBadInput;
  auto rig = LoadRigOrReport(args.rig);
  if (!rig) return kExitBadInput;
  std::string error;
  if (!MakeDirectories(args.out, &error)) return Fail(kExitBadInput, error);
  const std::string csv_path = args.out + "/bench_tracking.csv";
  std::ofstream csv(csv_path);
  if (!csv) return Fail(kExitBadInput, "cannot write '" + csv_path + "'");
  std::ofstream fcsv;
  if (args.frames_csv) {
    fcsv.open(args.out + "/bench_tracking_frames.csv");
    if (!fcsv) return Fail(kExitBadInput, "cannot write the frames CSV");
    fcsv << "size,frame,setting,tank_rot_deg,pen_rot_deg,tip_mm,flip,"
            "pen_faces_visible,pen_face_px,pen_status,pen_tags,"
            "pen_flip_rejected,pen_jumped,pen_ambiguous\n";
  }
  csv << "size,frames,setting,ms_median,ms_p95,tank_rot_deg_median,"
         "tank_rot_deg_p95,tank_mm_median,tank_mm_p95,pen_rot_deg_median,"
         "pen_rot_deg_p95,tip_mm_median,tip_mm_p95,flips,tank_tracked_share,"
         "pen_tracked_share\n";
  for (const std::string& size : args.sizes) {
    int w = 0, h = 0;
    char x = 0;
    std::istringstream in(size);
    if (!(in >> w >> x >> h) || x != 'x' || w <= 0 || h <= 0)
      return Fail(kExitBadInput, "--sizes: '" + size + "' is not WIDTHxHEIGHT");
    const tracking::Camera camera = base_camera->Scaled(w, h);
    synth::SequenceOptions seq;
    seq.preset = "benchmark";
    seq.frames = args.frames;
    seq.seed = args.seed;
    std::vector<synth::FrameSpec> specs;
    if (!synth::MakeSequence(camera, *rig, seq, &specs, &error))
      return Fail(kExitBadInput, error);
    synth::SceneRenderer renderer(camera, *rig);
    auto settings = MakeSettings(args.sweep, args.threads);
    std::map<double, std::unique_ptr<tracking::TagDetector>> detectors;
    for (auto& s : settings) {
      if (s->baseline != Baseline::kNone) continue;
      s->tracker =
          std::make_unique<tracking::Tracker>(camera, *rig, s->options);
      const double d = s->options.detector.quad_decimate;
      if (!detectors.count(d)) {
        tracking::TagDetectorOptions o = s->options.detector;
        o.family = rig->family;
        detectors[d] = std::make_unique<tracking::TagDetector>(o);
      }
    }
    const double default_d = tracking::TagDetectorOptions{}.quad_decimate;
    if (!detectors.count(default_d)) {
      tracking::TagDetectorOptions o;
      o.family = rig->family;
      o.threads = args.threads;
      detectors[default_d] = std::make_unique<tracking::TagDetector>(o);
    }
    double render_ms = 0;
    const double start = NowMs();
    for (const synth::FrameSpec& spec : specs) {
      if (spec.index < args.first) continue;
      const double r0 = NowMs();
      const synth::RenderedFrame frame =
          renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
      render_ms += NowMs() - r0;
      cv::Mat gray;
      cv::cvtColor(frame.image, gray, cv::COLOR_BGR2GRAY);
      // Shared full-frame detections (grey conversion charged to each).
      std::map<double, std::pair<std::vector<tracking::TagDetection>, double>>
          shared;
      for (auto& [d, detector] : detectors) {
        const double t0 = NowMs();
        cv::Mat g;
        cv::cvtColor(frame.image, g, cv::COLOR_BGR2GRAY);
        auto dets = detector->Detect(g);
        shared[d] = {std::move(dets), NowMs() - t0};
      }
      for (auto& s : settings) {
        Outcome o;
        std::string pen_status = "";
        if (s->baseline != Baseline::kNone) {
          const auto& [dets, ms] = shared[default_d];
          o = RunBaseline(s->baseline, camera, *rig, dets);
          o.ms += ms;
        } else {
          tracking::FrameResult r;
          if (s->options.roi.enabled) {
            r = s->tracker->Track(frame.image, spec.time_s);
          } else {
            const auto& [dets, ms] = shared[s->options.detector.quad_decimate];
            r = s->tracker->TrackDetections(dets, spec.time_s, ms, &gray);
          }
          o.tank = r.tank.cam_from_object;
          o.pen = r.pen.cam_from_object;
          o.tank_tracked = r.tank.status == tracking::TrackStatus::kTracked;
          o.pen_tracked = r.pen.status == tracking::TrackStatus::kTracked;
          o.ms = r.timings.total_ms;
          for (int id : r.pen.tags)
            o.pen_tags += (o.pen_tags.empty() ? "" : "+") + std::to_string(id);
          o.pen_flip_rejected = r.pen.flip_rejected;
          o.pen_jumped = r.pen.jumped;
          o.pen_ambiguous = r.pen.ambiguous;
          pen_status = tracking::ToString(r.pen.status);
        }
        const FrameErrors fe = Accumulate(*rig, spec, frame, o, s.get());
        if (fcsv.is_open()) {
          double face_px = 0;
          for (const tracking::TagDetection& d : shared[default_d].first)
            if (rig->pen)
              for (const tracking::TagPlacement& f : rig->pen->faces)
                if (f.id == d.id) face_px = std::max(face_px, d.SizePx());
          fcsv << size << ',' << spec.index << ",\"" << s->name << "\","
               << fe.tank_rot_deg << ',' << fe.pen_rot_deg << ',' << fe.tip_mm
               << ',' << fe.flip << ',' << frame.pen_tags.size() << ','
               << face_px << ',' << pen_status << ',' << o.pen_tags << ','
               << o.pen_flip_rejected << ',' << o.pen_jumped << ','
               << o.pen_ambiguous << '\n';
        }
      }
      if ((spec.index + 1) % 50 == 0)
        std::fprintf(stderr, "\rbench tracking %s: %d/%zu frames", size.c_str(),
                     spec.index + 1, specs.size());
    }
    std::fprintf(stderr, "\n");
    std::printf(
        "\n### %s, %d frames of synth's benchmark preset (seed %llu), %d "
        "detector thread(s); rendering took %.1f s, tracking %.1f s\n\n",
        size.c_str(), args.frames, static_cast<unsigned long long>(args.seed),
        args.threads, render_ms / 1000, (NowMs() - start - render_ms) / 1000);
    std::printf(
        "| # | setting | ms/frame | tank rot ° med / p95 | tank mm med / p95 | "
        "pen rot ° med / p95 | tip mm med / p95 | flips | tracked tank / pen "
        "|\n|---|---|---|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < settings.size(); ++i) {
      const Setting& s = *settings[i];
      const double tank_share =
          double(s.tank_tracked) / std::max(1, s.tank_visible);
      const double pen_share =
          double(s.pen_tracked) / std::max(1, s.pen_visible);
      std::printf(
          "| %zu | %s | %.2f | %.3f / %.3f | %.2f / %.2f | %.2f / %.2f | "
          "%.2f / %.2f | %d | %.1f%% / %.1f%% |\n",
          i + 1, s.name.c_str(), Percentile(s.ms, 0.5),
          Percentile(s.tank_rot, 0.5), Percentile(s.tank_rot, 0.95),
          Percentile(s.tank_mm, 0.5), Percentile(s.tank_mm, 0.95),
          Percentile(s.pen_rot, 0.5), Percentile(s.pen_rot, 0.95),
          Percentile(s.tip_mm, 0.5), Percentile(s.tip_mm, 0.95), s.flips,
          100 * tank_share, 100 * pen_share);
      csv << size << ',' << args.frames << ",\"" << s.name << "\","
          << Percentile(s.ms, 0.5) << ',' << Percentile(s.ms, 0.95) << ','
          << Percentile(s.tank_rot, 0.5) << ',' << Percentile(s.tank_rot, 0.95)
          << ',' << Percentile(s.tank_mm, 0.5) << ','
          << Percentile(s.tank_mm, 0.95) << ',' << Percentile(s.pen_rot, 0.5)
          << ',' << Percentile(s.pen_rot, 0.95) << ','
          << Percentile(s.tip_mm, 0.5) << ',' << Percentile(s.tip_mm, 0.95)
          << ',' << s.flips << ',' << tank_share << ',' << pen_share << '\n';
    }
    std::fflush(stdout);
    Plot(settings,
         "ripple bench tracking, " + size + ", " + std::to_string(args.frames) +
             " frames: tip error against time",
         args.out + "/bench_tracking_" + size + ".png");
  }
  std::printf("\nwrote %s and %s/bench_tracking_<size>.png\n", csv_path.c_str(),
              args.out.c_str());
  return kExitOk;
}

CommandAction SetupBenchTracking(CLI::App* sub) {
  auto args = std::make_shared<BenchArgs>();
  sub->add_option("--camera", args->camera,
                  "Camera calibration YAML (scaled to each size)")
      ->capture_default_str();
  sub->add_option("--rig", args->rig, "Rig YAML")->capture_default_str();
  sub->add_option("--out", args->out, "Output folder (CSV, PNG plots)")
      ->capture_default_str();
  sub->add_option("--frames", args->frames, "Frames per size")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  sub->add_option("--sizes", args->sizes, "Image sizes, WIDTHxHEIGHT")
      ->capture_default_str()
      ->delimiter(',');
  sub->add_option("--sweep", args->sweep,
                  "full: decimation x refinement x pen mode x region search; "
                  "short: one factor at a time around the default; "
                  "default: the default setting only, no baselines")
      ->capture_default_str()
      ->check(CLI::IsMember({"full", "short", "default"}));
  sub->add_option("--first", args->first,
                  "Skip (neither render nor track) the frames before this one "
                  "of the sequence (to look at one segment)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100000));
  sub->add_flag("--frames-csv", args->frames_csv,
                "Also write per-frame errors of every setting to "
                "bench_tracking_frames.csv");
  sub->add_option("--threads", args->threads, "Detector threads")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  sub->add_option("--seed", args->seed, "Sequence seed")->capture_default_str();
  return [args] { return RunBenchTracking(*args); };
}

}  // namespace

RIPPLE_REGISTER_BENCH(tracking,
                      "Tracking run time against error on synth frames",
                      SetupBenchTracking);

}  // namespace ripple::app
