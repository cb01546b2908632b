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
#include "tracking/synth/variant.h"

namespace ripple::bench {
namespace {

using tracking::Pose;

constexpr double kDeg = M_PI / 180.0;

// Run-time percentiles as the error table's.
double Pct(const std::vector<double>& v, double p) {
  return ErrorPercentile(v, p);
}

// Root mean square of per-segment deviations (NaN when none).
double Rms(const std::vector<double>& v) {
  if (v.empty()) return NAN;
  double ss = 0;
  for (double x : v) ss += x * x;
  return std::sqrt(ss / v.size());
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
  char buf[320];
  std::snprintf(
      buf, sizeof(buf), "d%g %s%s%s %s%s%s", o.detector.quad_decimate,
      o.pen_mode == tracking::PenMode::kJoint ? "joint" : "best-face",
      o.pen_mode == tracking::PenMode::kBestFace &&
              o.face_selection == tracking::FaceSelection::kMostFrontal
          ? "(frontal)"
          : "",
      o.pose.refine ? " ceres" : " ippe", o.roi.enabled ? "roi" : "full",
      o.pen_dense.enabled ? " dense" : "", o.pen_shaft.enabled ? " shaft" : "");
  std::string name = buf;
  // What a suspects sweep changes beyond the factors above.
  const tracking::TrackerOptions d;
  if (!o.detector.edge_fit) name += " no-edge-fit";
  if (o.detector.edge_fit && !o.detector.edge_fit_border_black)
    name += " local-dark";
  if (o.detector.edge_outward_px != d.detector.edge_outward_px) {
    std::snprintf(buf, sizeof(buf), " outward %g px",
                  o.detector.edge_outward_px);
    name += buf;
  }
  if (o.detector.pixel_offset_px != d.detector.pixel_offset_px) {
    std::snprintf(buf, sizeof(buf), " offset %g px",
                  o.detector.pixel_offset_px);
    name += buf;
  }
  if (o.pose.loss == tracking::RobustLoss::kNone) {
    name += " no-loss";
  } else if (o.pose.loss_scale_px != d.pose.loss_scale_px) {
    std::snprintf(buf, sizeof(buf), " loss %g px", o.pose.loss_scale_px);
    name += buf;
  }
  if (o.pose.weight_by_view_angle != d.pose.weight_by_view_angle)
    name += o.pose.weight_by_view_angle ? " view-weights" : " no-view-weights";
  if (o.pen_shaft.enabled && !o.pen_shaft.average_along)
    name += " shaft-one-line";
  if (o.pen_shaft.enabled && !o.pen_shaft.dense_prior)
    name += " shaft-corner-prior";
  if (o.pen_shaft.enabled && o.pen_shaft.dense_prior &&
      o.pen_shaft.dense_information_scale !=
          d.pen_shaft.dense_information_scale) {
    std::snprintf(buf, sizeof(buf), " shaft-prior x%g",
                  o.pen_shaft.dense_information_scale);
    name += buf;
  }
  if (o.smoothing.enabled != d.smoothing.enabled && !o.smoothing.enabled)
    name += " no-smoothing";
  if (o.smoothing.enabled) {
    // Pen translation cut-off / beta, pen rotation cut-off / beta, tank
    // cut-off, when not the defaults.
    const auto& p = o.smoothing.pen;
    const auto& t = o.smoothing.tank;
    const auto& dp = d.smoothing.pen;
    const auto& dt = d.smoothing.tank;
    const bool same =
        p.min_cutoff_translation_hz == dp.min_cutoff_translation_hz &&
        p.beta_translation_hz_per_m_s == dp.beta_translation_hz_per_m_s &&
        p.min_cutoff_rotation_hz == dp.min_cutoff_rotation_hz &&
        p.beta_rotation_hz_per_rad_s == dp.beta_rotation_hz_per_rad_s &&
        p.derivative_cutoff_hz == dp.derivative_cutoff_hz &&
        t.min_cutoff_rotation_hz == dt.min_cutoff_rotation_hz &&
        t.min_cutoff_translation_hz == dt.min_cutoff_translation_hz &&
        t.beta_translation_hz_per_m_s == dt.beta_translation_hz_per_m_s &&
        t.beta_rotation_hz_per_rad_s == dt.beta_rotation_hz_per_rad_s &&
        t.derivative_cutoff_hz == dt.derivative_cutoff_hz &&
        t.reset_rotation_deg == dt.reset_rotation_deg &&
        t.reset_translation_m == dt.reset_translation_m &&
        p.reset_rotation_deg == dp.reset_rotation_deg &&
        p.reset_translation_m == dp.reset_translation_m &&
        o.smoothing.reset_when_ambiguous == d.smoothing.reset_when_ambiguous;
    if (same) {
      name += " smooth";
    } else {
      // The --smoothing-grid spelling of the setting.
      std::snprintf(buf, sizeof(buf),
                    " smooth %g/%g/%g/%g/%g/%g/%g/%g/%g/%g/%g/%g/%g/%d",
                    p.min_cutoff_translation_hz, p.beta_translation_hz_per_m_s,
                    p.min_cutoff_rotation_hz, p.beta_rotation_hz_per_rad_s,
                    p.derivative_cutoff_hz, t.min_cutoff_rotation_hz,
                    t.beta_translation_hz_per_m_s, t.beta_rotation_hz_per_rad_s,
                    t.derivative_cutoff_hz, t.reset_rotation_deg,
                    1000 * t.reset_translation_m, p.reset_rotation_deg,
                    1000 * p.reset_translation_m,
                    o.smoothing.reset_when_ambiguous ? 1 : 0);
      name += buf;
    }
  }
  return name;
}

bool IsDefault(const tracking::TrackerOptions& o) {
  const tracking::TrackerOptions defaults;
  return o.detector.quad_decimate == defaults.detector.quad_decimate &&
         o.pen_mode == defaults.pen_mode &&
         o.pose.refine == defaults.pose.refine &&
         o.roi.enabled == defaults.roi.enabled &&
         o.pen_dense.enabled == defaults.pen_dense.enabled &&
         o.pen_shaft.enabled == defaults.pen_shaft.enabled &&
         o.face_selection == defaults.face_selection &&
         o.detector.edge_fit == defaults.detector.edge_fit &&
         o.detector.edge_fit_border_black ==
             defaults.detector.edge_fit_border_black &&
         o.detector.edge_outward_px == defaults.detector.edge_outward_px &&
         o.detector.pixel_offset_px == defaults.detector.pixel_offset_px &&
         o.pose.loss == defaults.pose.loss &&
         o.pose.loss_scale_px == defaults.pose.loss_scale_px &&
         o.pose.weight_by_view_angle == defaults.pose.weight_by_view_angle &&
         SettingName(o) == SettingName(defaults);
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
      case Baseline::kPlainSqpnpLm:
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

// Adds the frame's errors to the setting's samples (unless `row_only`) and
// fills the error fields of `row`.
void Accumulate(const tracking::Rig& rig, const synth::FrameSpec& spec,
                const synth::RenderedFrame& frame, const Outcome& o,
                TrackingSetting* s, TrackingFrameRow* row,
                bool row_only = false) {
  if (!row_only) s->ms.push_back(o.ms);
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
  const FrameErrors e =
      row_only ? ComputeFrameErrors(PoseErrorOptions{}, truth, estimate)
               : s->errors.Add(truth, estimate);
  row->tank_rot_deg = e.tank_rot_deg;
  row->pen_rot_deg = e.pen_rot_deg;
  row->tip_mm = e.tip_mm;
  row->tip_los_mm = row->tip_across_mm = std::nan("");
  if (estimate.tip_in_tank && truth.tip_in_tank) {
    const Eigen::Vector3d camera_in_tank =
        truth.cam_from_tank.Inverse() * Eigen::Vector3d::Zero();
    const Eigen::Vector3d los =
        (*truth.tip_in_tank - camera_in_tank).normalized();
    const Eigen::Vector3d d = *estimate.tip_in_tank - *truth.tip_in_tank;
    row->tip_los_mm = 1000 * d.dot(los);
    row->tip_across_mm = 1000 * (d - d.dot(los) * los).norm();
  }
  row->flip = e.flip;
}

}  // namespace

bool TrackingSetting::is_default() const {
  return baseline == Baseline::kNone && IsDefault(options);
}

std::vector<std::unique_ptr<TrackingSetting>> MakeTrackingSettings(
    Sweep sweep, int threads,
    const std::vector<tracking::SmoothingOptions>& smoothing_grid) {
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
  } else if (sweep == Sweep::kSmoothing) {
    tracking::TrackerOptions o = defaults;
    o.smoothing.enabled = !defaults.smoothing.enabled;
    list.push_back(defaults);
    list.push_back(o);
    // Without a grid: the default's parts one at a time (a looser tank
    // reset bound, restarting the pen while ambiguous, no pen reset bound).
    if (smoothing_grid.empty()) {
      o = defaults;
      o.smoothing.enabled = true;
      o.smoothing.tank.reset_rotation_deg = 0.05;
      o.smoothing.tank.reset_translation_m = 0.0003;
      list.push_back(o);
      o = defaults;
      o.smoothing.enabled = true;
      o.smoothing.reset_when_ambiguous = true;
      list.push_back(o);
      o = defaults;
      o.smoothing.enabled = true;
      o.smoothing.pen.reset_rotation_deg = 10;
      o.smoothing.pen.reset_translation_m = 0.03;
      list.push_back(o);
    }
    for (const tracking::SmoothingOptions& g : smoothing_grid) {
      tracking::TrackerOptions g_o = defaults;
      g_o.smoothing = g;
      list.push_back(g_o);
    }
  } else if (sweep == Sweep::kSuspects) {
    list.push_back(defaults);
    tracking::TrackerOptions o = defaults;
    o.detector.edge_fit = false;
    list.push_back(o);
    o = defaults;
    o.detector.edge_outward_px = -0.015;
    list.push_back(o);
    // The edge fit's former dark level (each profile's own) with and
    // without the outward correction that offset its bias.
    o = defaults;
    o.detector.edge_fit_border_black = false;
    list.push_back(o);
    o.detector.edge_outward_px = -0.015;
    list.push_back(o);
    for (double scale : {0.3, 3.0}) {
      o = defaults;
      o.pose.loss_scale_px = scale;
      list.push_back(o);
    }
    o = defaults;
    o.pose.loss = tracking::RobustLoss::kNone;
    list.push_back(o);
    o = defaults;
    o.pose.weight_by_view_angle = !defaults.pose.weight_by_view_angle;
    list.push_back(o);
    o = defaults;
    o.pen_dense.enabled = !defaults.pen_dense.enabled;
    list.push_back(o);
    o = defaults;
    o.pen_shaft.enabled = !defaults.pen_shaft.enabled;
    list.push_back(o);
    // The shaft step's parts: one profile per sample, the corners' prior,
    // the dense prior at full weight.
    o = defaults;
    o.pen_shaft.average_along = false;
    list.push_back(o);
    o = defaults;
    o.pen_shaft.dense_prior = false;
    list.push_back(o);
    o.pen_shaft.average_along = false;
    list.push_back(o);
    o = defaults;
    o.pen_shaft.dense_information_scale = 1.0;
    list.push_back(o);
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
    o = defaults;
    o.pen_shaft.enabled = !defaults.pen_shaft.enabled;
    list.push_back(o);
  }
  if (sweep == Sweep::kShort || sweep == Sweep::kFull) {
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
  auto add = [&](Baseline b, const char* name, double plain_decimate) {
    auto s = std::make_unique<TrackingSetting>();
    s->baseline = b;
    s->name = name;
    s->plain_decimate = plain_decimate;
    settings.push_back(std::move(s));
  };
  if (sweep != Sweep::kSuspects && sweep != Sweep::kSmoothing) {
    add(Baseline::kPaper, "paper: frontal face, estimate_tag_pose", 2);
    add(Baseline::kIppe, "opencv IPPE_SQUARE, best-posed face", 2);
  }
  if (sweep != Sweep::kSmoothing)
    add(Baseline::kSqpnpLm, "opencv SQPNP+LM, all corners", 2);
  add(Baseline::kPlainSqpnpLm,
      "plain: SQPNP+LM on apriltag corners -0.5 px, d2", 2);
  add(Baseline::kPlainSqpnpLm,
      "plain: SQPNP+LM on apriltag corners -0.5 px, d1", 1);
  return settings;
}

bool RunTrackingBench(const TrackingBenchOptions& options,
                      const tracking::Camera& base_camera,
                      const tracking::Rig& rig, bool keep_frame_rows,
                      const std::function<void(int, int)>& progress,
                      TrackingBenchResult* result, std::string* error) {
  synth::DataVariant variant;
  if (!synth::GetDataVariant(options.variant, &variant)) {
    if (error) *error = "unknown data variant '" + options.variant + "'";
    return false;
  }
  const tracking::Camera camera = synth::VariantCamera(variant, base_camera);
  synth::SequenceOptions seq;
  seq.preset = "benchmark";
  seq.frames = options.frames;
  seq.seed = options.seed;
  std::vector<synth::FrameSpec> specs, still;
  if (!synth::MakeSequence(camera, rig, seq, &specs, error)) return false;
  if (options.static_frames > 0) {
    seq.preset = "static";
    seq.frames = options.static_frames;
    seq.segment_frames = options.static_segment_frames;
    seq.seed = options.seed + 1000;
    if (!synth::MakeSequence(camera, rig, seq, &still, error)) return false;
  }
  for (auto* list : {&specs, &still})
    for (synth::FrameSpec& f : *list) synth::ApplyVariant(variant, &f.imaging);
  synth::SceneRenderer renderer(camera, rig, options.floor, variant.formation);
  result->settings = MakeTrackingSettings(options.sweep, options.threads,
                                          options.smoothing_grid);
  auto& settings = result->settings;
  // Every detector decodes the frames as the variant's camera file says,
  // as `ripple track` does (the plain baseline's libapriltag corners do not
  // depend on it).
  for (auto& s : settings) s->options.detector.transfer = camera.transfer;
  std::map<double, std::unique_ptr<tracking::TagDetector>> detectors;
  // libapriltag's corners moved by the pixel offset only, per decimation.
  std::map<double, std::unique_ptr<tracking::TagDetector>> plain_detectors;
  const double default_d = tracking::TagDetectorOptions{}.quad_decimate;
  auto make_trackers = [&] {
    for (auto& s : settings)
      if (s->baseline == Baseline::kNone)
        s->tracker =
            std::make_unique<tracking::Tracker>(camera, rig, s->options);
  };
  make_trackers();
  for (auto& s : settings) {
    if (s->baseline == Baseline::kPlainSqpnpLm) {
      tracking::TagDetectorOptions o;
      o.family = rig.family;
      o.threads = options.threads;
      o.quad_decimate = s->plain_decimate;
      o.edge_fit = false;
      o.edge_outward_px = 0;
      o.transfer = camera.transfer;
      plain_detectors[s->plain_decimate] =
          std::make_unique<tracking::TagDetector>(o);
      continue;
    }
    if (s->baseline != Baseline::kNone) continue;
    const double d = s->options.detector.quad_decimate;
    // Settings without region search share a detection per decimation when
    // their detector options are the default's.
    tracking::TagDetectorOptions o = s->options.detector;
    o.family = rig.family;
    tracking::TagDetectorOptions def;
    def.family = rig.family;
    def.transfer = camera.transfer;
    def.quad_decimate = d;
    def.threads = o.threads;
    if (!detectors.count(d) && o.edge_fit == def.edge_fit &&
        o.edge_fit_border_black == def.edge_fit_border_black &&
        o.edge_outward_px == def.edge_outward_px &&
        o.pixel_offset_px == def.pixel_offset_px)
      detectors[d] = std::make_unique<tracking::TagDetector>(o);
  }
  if (!detectors.count(default_d)) {
    tracking::TagDetectorOptions o;
    o.family = rig.family;
    o.threads = options.threads;
    o.transfer = camera.transfer;
    detectors[default_d] = std::make_unique<tracking::TagDetector>(o);
  }
  // Per setting, the current static segment's tip and rotations.
  struct StaticSamples {
    std::vector<Eigen::Vector3d> tip;
    std::vector<Pose> pen, tank;
  };
  std::vector<StaticSamples> samples(settings.size());
  auto mean_rotation = [](const std::vector<Pose>& poses) {
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (const Pose& p : poses) {
      Eigen::Vector4d q = p.rotation.coeffs();
      if (q.dot(poses.front().rotation.coeffs()) < 0) q = -q;
      sum += q;
    }
    Eigen::Quaterniond m;
    m.coeffs() = sum.normalized();
    return m;
  };
  auto rms_rotation_deg = [&](const std::vector<Pose>& poses) {
    const Eigen::Quaterniond m = mean_rotation(poses);
    double ss = 0;
    for (const Pose& p : poses) {
      const double a = p.rotation.angularDistance(m) / kDeg;
      ss += a * a;
    }
    return std::sqrt(ss / poses.size());
  };
  // Closes a static segment: its jitter into each setting's samples.
  auto close_segment = [&] {
    for (size_t i = 0; i < settings.size(); ++i) {
      StaticSamples& st = samples[i];
      TrackingSetting& s = *settings[i];
      if (st.tip.size() >= 2) {
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (const auto& t : st.tip) mean += t;
        mean /= st.tip.size();
        double ss = 0;
        for (const auto& t : st.tip) ss += (t - mean).squaredNorm();
        s.jitter_tip_mm.push_back(1000 * std::sqrt(ss / st.tip.size()));
      }
      if (st.pen.size() >= 2)
        s.jitter_pen_rot_deg.push_back(rms_rotation_deg(st.pen));
      if (st.tank.size() >= 2)
        s.jitter_tank_rot_deg.push_back(rms_rotation_deg(st.tank));
      st = StaticSamples();
    }
  };
  double render_ms = 0;
  const Stopwatch total;
  const int total_frames = static_cast<int>(specs.size() + still.size());
  int done = 0;
  auto run_frame = [&](const synth::FrameSpec& spec, bool is_static) {
    const Stopwatch render_watch;
    const synth::RenderedFrame frame =
        renderer.Render(spec.scene, spec.imaging, spec.noise_seed);
    render_ms += render_watch.ElapsedMs();
    cv::Mat gray;
    cv::cvtColor(frame.image, gray, cv::COLOR_BGR2GRAY);
    // Shared full-frame detections (grey conversion charged to each).
    std::map<double, std::pair<std::vector<tracking::TagDetection>, double>>
        shared, plain;
    auto detect = [&](auto& from, auto* into) {
      for (auto& [d, detector] : from) {
        const Stopwatch detect_watch;
        cv::Mat g;
        cv::cvtColor(frame.image, g, cv::COLOR_BGR2GRAY);
        auto dets = detector->Detect(g);
        (*into)[d] = {std::move(dets), detect_watch.ElapsedMs()};
      }
    };
    detect(detectors, &shared);
    detect(plain_detectors, &plain);
    for (size_t si = 0; si < settings.size(); ++si) {
      TrackingSetting* s = settings[si].get();
      Outcome o;
      std::string pen_status;
      if (s->baseline != Baseline::kNone) {
        const auto& [dets, ms] = s->baseline == Baseline::kPlainSqpnpLm
                                     ? plain[s->plain_decimate]
                                     : shared[default_d];
        o = RunBaseline(s->baseline, camera, rig, dets);
        o.ms += ms;
      } else {
        tracking::FrameResult r;
        const double d = s->options.detector.quad_decimate;
        if (s->options.roi.enabled || !detectors.count(d) ||
            detectors[d]->options().edge_fit != s->options.detector.edge_fit ||
            detectors[d]->options().edge_fit_border_black !=
                s->options.detector.edge_fit_border_black ||
            detectors[d]->options().edge_outward_px !=
                s->options.detector.edge_outward_px ||
            detectors[d]->options().pixel_offset_px !=
                s->options.detector.pixel_offset_px) {
          r = s->tracker->Track(frame.image, spec.time_s);
        } else {
          const auto& [dets, ms] = shared[d];
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
      if (is_static) {
        if (keep_frame_rows) {
          Accumulate(rig, spec, frame, o, s, &row, true);
          row.is_static = true;
        }
        StaticSamples& st = samples[si];
        if (o.tank && o.tank_tracked) st.tank.push_back(*o.tank);
        if (o.pen && o.pen_tracked) {
          st.pen.push_back(*o.pen);
          if (o.tank && o.tank_tracked)
            st.tip.push_back(o.tank->Inverse() *
                             (*o.pen * rig.pen->tip_in_pen));
        }
      } else {
        Accumulate(rig, spec, frame, o, s, &row);
      }
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
      row.motion_blur_px = spec.imaging.motion_blur_px;
      row.defocus_px = spec.imaging.defocus_sigma_px;
      row.occluders = static_cast<int>(spec.scene.occluders.size());
      result->frame_rows.push_back(std::move(row));
    }
    if (++done % 50 == 0 && progress) progress(done, total_frames);
  };
  for (const synth::FrameSpec& spec : specs)
    if (spec.index >= options.first) run_frame(spec, false);
  for (size_t i = 0; i < still.size(); ++i) {
    if (i % options.static_segment_frames == 0) {
      if (i > 0) close_segment();
      make_trackers();  // each static segment starts afresh
    }
    run_frame(still[i], true);
  }
  if (!still.empty() && rig.pen) close_segment();
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
      "\n### %s, %s frames, %d frames of synth's benchmark preset (seed "
      "%llu, %s floor), %d static; %d detector thread(s); rendering took "
      "%.1f s, tracking %.1f s\n\n",
      size.c_str(), options.variant.c_str(), options.frames,
      static_cast<unsigned long long>(options.seed),
      synth::ToString(options.floor.kind()), options.static_frames,
      options.threads, result.render_s, result.tracking_s);
  out += buf;
  out += "| # | setting | ms/frame " + ErrorTableHeaderCells() +
         "| static pen: jitter tip mm / pen ° / tank ° |\n|---|---|---" +
         ErrorTableSeparatorCells() + "|---|\n";
  for (size_t i = 0; i < result.settings.size(); ++i) {
    const TrackingSetting& s = *result.settings[i];
    std::snprintf(buf, sizeof(buf), "| %zu | %s | %.2f ", i + 1, s.name.c_str(),
                  Pct(s.ms, 50));
    out += buf + ErrorTableCells(s.errors.Summarize());
    std::snprintf(buf, sizeof(buf), "| %.3f / %.4f / %.4f |\n",
                  Rms(s.jitter_tip_mm), Rms(s.jitter_pen_rot_deg),
                  Rms(s.jitter_tank_rot_deg));
    out += buf;
  }
  return out;
}

void WriteTrackingCsvHeader(std::ostream* csv) {
  *csv << "size,frames,setting,ms_median,ms_p95," << ErrorCsvHeader()
       << ",variant,static_jitter_tip_mm,static_jitter_pen_rot_deg,"
          "static_jitter_tank_rot_deg\n";
}

void WriteTrackingCsvRows(const TrackingBenchOptions& options,
                          const std::string& size,
                          const TrackingBenchResult& result,
                          std::ostream* csv) {
  for (const auto& setting : result.settings) {
    const TrackingSetting& s = *setting;
    *csv << size << ',' << options.frames << ",\"" << s.name << "\","
         << Pct(s.ms, 50) << ',' << Pct(s.ms, 95) << ','
         << ErrorCsvFields(s.errors.Summarize()) << ',' << options.variant
         << ',' << Rms(s.jitter_tip_mm) << ',' << Rms(s.jitter_pen_rot_deg)
         << ',' << Rms(s.jitter_tank_rot_deg) << '\n';
  }
}

void WriteTrackingFramesCsvHeader(std::ostream* csv) {
  *csv << "size,frame,setting,tank_rot_deg,pen_rot_deg,tip_mm,tip_los_mm,"
          "tip_across_mm,flip,"
          "pen_faces_visible,pen_face_px,pen_status,pen_tags,"
          "pen_flip_rejected,pen_jumped,pen_ambiguous,motion_blur_px,"
          "defocus_px,occluders,static\n";
}

void WriteTrackingFramesCsvRows(const std::string& size,
                                const TrackingBenchResult& result,
                                std::ostream* csv) {
  for (const TrackingFrameRow& r : result.frame_rows)
    *csv << size << ',' << r.frame << ",\"" << r.setting << "\","
         << r.tank_rot_deg << ',' << r.pen_rot_deg << ',' << r.tip_mm << ','
         << r.tip_los_mm << ',' << r.tip_across_mm << ',' << r.flip << ','
         << r.pen_faces_visible << ',' << r.pen_face_px << ',' << r.pen_status
         << ',' << r.pen_tags << ',' << r.pen_flip_rejected << ','
         << r.pen_jumped << ',' << r.pen_ambiguous << ',' << r.motion_blur_px
         << ',' << r.defocus_px << ',' << r.occluders << ',' << r.is_static
         << '\n';
}

}  // namespace ripple::bench
