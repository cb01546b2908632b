#include "bench/tracking_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <utility>

#include "bench/stats.h"
#include "tracking/baselines.h"
#include "tracking/synth/synth.h"

namespace ripple::bench {
namespace {

using tracking::Pose;

// Run-time percentiles as the error table's: rounded rank, NaN when empty.
double Pct(const std::vector<double>& v, double p) {
  PercentileOptions options;
  options.rank = PercentileOptions::Rank::kRounded;
  options.empty_value = NAN;
  return Percentile(v, p, options);
}

// What one setting produced on one frame.
struct Outcome {
  std::optional<Pose> tank, pen;
  bool tank_tracked = false, pen_tracked = false;
  double ms = 0;
  std::string pen_tags;  // faces used, '+'-separated (settings only)
  bool pen_flip_rejected = false, pen_jumped = false, pen_ambiguous = false;
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

bool IsDefault(const tracking::TrackerOptions& o) {
  const tracking::TrackerOptions defaults;
  return o.detector.quad_decimate == defaults.detector.quad_decimate &&
         o.pen_mode == defaults.pen_mode &&
         o.pose.refine == defaults.pose.refine &&
         o.roi.enabled == defaults.roi.enabled &&
         o.pen_dense.enabled == defaults.pen_dense.enabled &&
         o.face_selection == defaults.face_selection;
}

Outcome RunBaseline(Baseline b, const tracking::Camera& camera,
                    const tracking::Rig& rig,
                    const std::vector<tracking::TagDetection>& dets) {
  Outcome o;
  const Stopwatch watch;
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
  o.ms = watch.ElapsedMs();
  return o;
}

// Adds the frame's errors to the setting's samples and fills the error
// fields of `row`.
void Accumulate(const tracking::Rig& rig, const synth::FrameSpec& spec,
                const synth::RenderedFrame& frame, const Outcome& o,
                TrackingSetting* s, TrackingFrameRow* row) {
  s->ms.push_back(o.ms);
  TruthFrame truth;
  truth.frame = spec.index;
  truth.cam_from_tank = spec.scene.cam_from_tank;
  truth.tank_visible = !frame.tank_tags.empty();
  truth.pen_visible = !frame.pen_tags.empty();
  EstimateFrame estimate;
  estimate.cam_from_tank = o.tank;
  estimate.tank_tracked = o.tank_tracked;
  estimate.pen_tracked = o.pen_tracked;
  if (spec.scene.tank_from_pen && rig.pen) {
    truth.cam_from_pen = spec.scene.cam_from_tank * *spec.scene.tank_from_pen;
    truth.tip_in_tank = *spec.scene.tank_from_pen * rig.pen->tip_in_pen;
    estimate.cam_from_pen = o.pen;
    if (o.tank && o.pen)
      estimate.tip_in_tank = o.tank->Inverse() * (*o.pen * rig.pen->tip_in_pen);
  }
  const FrameErrors e = s->errors.Add(truth, estimate);
  row->tank_rot_deg = e.tank_rot_deg;
  row->pen_rot_deg = e.pen_rot_deg;
  row->tip_mm = e.tip_mm;
  row->flip = e.flip;
}

}  // namespace

bool TrackingSetting::is_default() const {
  return baseline == Baseline::kNone && IsDefault(options);
}

std::vector<std::unique_ptr<TrackingSetting>> MakeTrackingSettings(
    Sweep sweep, int threads) {
  const tracking::TrackerOptions defaults;
  std::vector<tracking::TrackerOptions> list;
  if (sweep == Sweep::kFull) {
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
  } else if (sweep == Sweep::kDefault) {
    list.push_back(defaults);
  } else {
    list.push_back(defaults);
    for (double d : {1.0, 1.5, 2.0, 3.0, 4.0}) {
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
  if (sweep != Sweep::kDefault) {
    tracking::TrackerOptions frontal = defaults;
    frontal.pen_mode = tracking::PenMode::kBestFace;
    frontal.face_selection = tracking::FaceSelection::kMostFrontal;
    list.push_back(frontal);
  }
  std::vector<std::unique_ptr<TrackingSetting>> settings;
  for (tracking::TrackerOptions& o : list) {
    o.detector.threads = threads;
    auto s = std::make_unique<TrackingSetting>();
    s->options = o;
    s->name = SettingName(o);
    if (IsDefault(o)) s->name += " [default]";
    settings.push_back(std::move(s));
  }
  if (sweep == Sweep::kDefault) return settings;
  for (auto [b, name] :
       {std::make_pair(Baseline::kPaper,
                       "paper: frontal face, estimate_tag_pose"),
        std::make_pair(Baseline::kIppe, "opencv IPPE_SQUARE, best-posed face"),
        std::make_pair(Baseline::kSqpnpLm, "opencv SQPNP+LM, all corners")}) {
    auto s = std::make_unique<TrackingSetting>();
    s->baseline = b;
    s->name = name;
    settings.push_back(std::move(s));
  }
  return settings;
}

bool RunTrackingBench(const TrackingBenchOptions& options,
                      const tracking::Camera& camera, const tracking::Rig& rig,
                      bool keep_frame_rows,
                      const std::function<void(int, int)>& progress,
                      TrackingBenchResult* result, std::string* error) {
  synth::SequenceOptions seq;
  seq.preset = "benchmark";
  seq.frames = options.frames;
  seq.seed = options.seed;
  std::vector<synth::FrameSpec> specs;
  if (!synth::MakeSequence(camera, rig, seq, &specs, error)) return false;
  synth::SceneRenderer renderer(camera, rig, options.floor);
  result->settings = MakeTrackingSettings(options.sweep, options.threads);
  auto& settings = result->settings;
  std::map<double, std::unique_ptr<tracking::TagDetector>> detectors;
  for (auto& s : settings) {
    if (s->baseline != Baseline::kNone) continue;
    s->tracker = std::make_unique<tracking::Tracker>(camera, rig, s->options);
    const double d = s->options.detector.quad_decimate;
    if (!detectors.count(d)) {
      tracking::TagDetectorOptions o = s->options.detector;
      o.family = rig.family;
      detectors[d] = std::make_unique<tracking::TagDetector>(o);
    }
  }
  const double default_d = tracking::TagDetectorOptions{}.quad_decimate;
  if (!detectors.count(default_d)) {
    tracking::TagDetectorOptions o;
    o.family = rig.family;
    o.threads = options.threads;
    detectors[default_d] = std::make_unique<tracking::TagDetector>(o);
  }
  double render_ms = 0;
  const Stopwatch total;
  for (const synth::FrameSpec& spec : specs) {
    if (spec.index < options.first) continue;
    const Stopwatch render_watch;
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    render_ms += render_watch.ElapsedMs();
    cv::Mat gray;
    cv::cvtColor(frame.image, gray, cv::COLOR_BGR2GRAY);
    // Shared full-frame detections (grey conversion charged to each).
    std::map<double, std::pair<std::vector<tracking::TagDetection>, double>>
        shared;
    for (auto& [d, detector] : detectors) {
      const Stopwatch detect_watch;
      cv::Mat g;
      cv::cvtColor(frame.image, g, cv::COLOR_BGR2GRAY);
      auto dets = detector->Detect(g);
      shared[d] = {std::move(dets), detect_watch.ElapsedMs()};
    }
    for (auto& s : settings) {
      Outcome o;
      std::string pen_status;
      if (s->baseline != Baseline::kNone) {
        const auto& [dets, ms] = shared[default_d];
        o = RunBaseline(s->baseline, camera, rig, dets);
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
      TrackingFrameRow row;
      Accumulate(rig, spec, frame, o, s.get(), &row);
      if (!keep_frame_rows) continue;
      row.frame = spec.index;
      row.setting = s->name;
      row.pen_faces_visible = static_cast<int>(frame.pen_tags.size());
      for (const tracking::TagDetection& d : shared[default_d].first)
        if (rig.pen)
          for (const tracking::TagPlacement& f : rig.pen->faces)
            if (f.id == d.id)
              row.pen_face_px = std::max(row.pen_face_px, d.SizePx());
      row.pen_status = pen_status;
      row.pen_tags = o.pen_tags;
      row.pen_flip_rejected = o.pen_flip_rejected;
      row.pen_jumped = o.pen_jumped;
      row.pen_ambiguous = o.pen_ambiguous;
      result->frame_rows.push_back(std::move(row));
    }
    if ((spec.index + 1) % 50 == 0 && progress)
      progress(spec.index + 1, static_cast<int>(specs.size()));
  }
  result->render_s = render_ms / 1000;
  result->tracking_s = (total.ElapsedMs() - render_ms) / 1000;
  return true;
}

std::string FormatTrackingTable(const TrackingBenchOptions& options,
                                const std::string& size,
                                const TrackingBenchResult& result) {
  std::string out;
  char buf[1024];
  std::snprintf(
      buf, sizeof(buf),
      "\n### %s, %d frames of synth's benchmark preset (seed %llu, %s "
      "floor), %d detector thread(s); rendering took %.1f s, tracking %.1f "
      "s\n\n",
      size.c_str(), options.frames,
      static_cast<unsigned long long>(options.seed),
      synth::ToString(options.floor.kind()), options.threads, result.render_s,
      result.tracking_s);
  out += buf;
  out += "| # | setting | ms/frame " + ErrorTableHeaderCells() +
         "|\n|---|---|---" + ErrorTableSeparatorCells() + "|\n";
  for (size_t i = 0; i < result.settings.size(); ++i) {
    const TrackingSetting& s = *result.settings[i];
    std::snprintf(buf, sizeof(buf), "| %zu | %s | %.2f ", i + 1, s.name.c_str(),
                  Pct(s.ms, 50));
    out += buf + ErrorTableCells(s.errors.Summarize()) + "|\n";
  }
  return out;
}

void WriteTrackingCsvHeader(std::ostream* csv) {
  *csv << "size,frames,setting,ms_median,ms_p95," << ErrorCsvHeader() << '\n';
}

void WriteTrackingCsvRows(const TrackingBenchOptions& options,
                          const std::string& size,
                          const TrackingBenchResult& result,
                          std::ostream* csv) {
  for (const auto& setting : result.settings) {
    const TrackingSetting& s = *setting;
    *csv << size << ',' << options.frames << ",\"" << s.name << "\","
         << Pct(s.ms, 50) << ',' << Pct(s.ms, 95) << ','
         << ErrorCsvFields(s.errors.Summarize()) << '\n';
  }
}

void WriteTrackingFramesCsvHeader(std::ostream* csv) {
  *csv << "size,frame,setting,tank_rot_deg,pen_rot_deg,tip_mm,flip,"
          "pen_faces_visible,pen_face_px,pen_status,pen_tags,"
          "pen_flip_rejected,pen_jumped,pen_ambiguous\n";
}

void WriteTrackingFramesCsvRows(const std::string& size,
                                const TrackingBenchResult& result,
                                std::ostream* csv) {
  for (const TrackingFrameRow& r : result.frame_rows)
    *csv << size << ',' << r.frame << ",\"" << r.setting << "\","
         << r.tank_rot_deg << ',' << r.pen_rot_deg << ',' << r.tip_mm << ','
         << r.flip << ',' << r.pen_faces_visible << ',' << r.pen_face_px << ','
         << r.pen_status << ',' << r.pen_tags << ',' << r.pen_flip_rejected
         << ',' << r.pen_jumped << ',' << r.pen_ambiguous << '\n';
}

}  // namespace ripple::bench
