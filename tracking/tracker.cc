#include "tracking/tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "geometry/check.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

double NowMs() {
  return std::chrono::duration<double, std::milli>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

TrackerOptions WithRigFamily(TrackerOptions options, const Rig& rig) {
  options.detector.family = rig.family;
  return options;
}

// The detector's options, its lens the camera's unless the options name
// one: the edge fit's lines are straight in the lens's undistorted pixels.
TagDetectorOptions ValidDetectorOptions(const TrackerOptions& options,
                                        const Camera& camera) {
  std::string error;
  RIPPLE_CHECK(options.IsValid(&error), "Tracker: invalid options: " + error);
  TagDetectorOptions detector = options.detector;
  if (!detector.lens) detector.lens = camera;
  return detector;
}

}  // namespace

const char* ToString(PenMode mode) {
  return mode == PenMode::kJoint ? "joint" : "best-face";
}
const char* ToString(FaceSelection selection) {
  return selection == FaceSelection::kLeastUncertain ? "uncertainty"
                                                     : "frontal";
}
std::optional<PenMode> ParsePenMode(const std::string& s) {
  if (s == "joint") return PenMode::kJoint;
  if (s == "best-face") return PenMode::kBestFace;
  return std::nullopt;
}
std::optional<FaceSelection> ParseFaceSelection(const std::string& s) {
  if (s == "uncertainty") return FaceSelection::kLeastUncertain;
  if (s == "frontal") return FaceSelection::kMostFrontal;
  return std::nullopt;
}

// Chosen on `ripple bench tracking --sweep smoothing` (docs/tracking.md).
PoseFilterOptions SmoothingOptions::DefaultTankFilter() {
  PoseFilterOptions o;
  // The board rests while the camera may move: no speed adaptation, a plain
  // 1 Hz low-pass that restarts as soon as the measurement leaves the
  // noise (the tank's static jitter is 0.014-0.027 degrees).
  o.min_cutoff_translation_hz = 1.0;
  o.min_cutoff_rotation_hz = 1.0;
  o.beta_translation_hz_per_m_s = 0;
  o.beta_rotation_hz_per_rad_s = 0;
  o.reset_rotation_deg = 0.04;
  o.reset_translation_m = 0.0002;
  return o;
}

PoseFilterOptions SmoothingOptions::DefaultPenFilter() {
  PoseFilterOptions o;
  o.min_cutoff_translation_hz = 1.0;
  o.beta_translation_hz_per_m_s = 100.0;
  o.min_cutoff_rotation_hz = 0.5;
  o.beta_rotation_hz_per_rad_s = 10.0;
  // A tip that moves more than 1 mm (or turns 1 degree) from the filtered
  // pose in one frame is followed at once: the filter smooths a pen at rest
  // or creeping, never a stroke.
  o.reset_rotation_deg = 1.0;
  o.reset_translation_m = 0.001;
  return o;
}

bool SmoothingOptions::IsValid(std::string* error) const {
  if (!(bridge_loss_s >= 0)) {
    if (error) *error = "smoothing bridge_loss_s must be >= 0 (s)";
    return false;
  }
  std::string what;
  if (!tank.IsValid(&what)) {
    if (error) *error = "tank " + what;
    return false;
  }
  if (!pen.IsValid(&what)) {
    if (error) *error = "pen " + what;
    return false;
  }
  return true;
}

bool TrackerOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!detector.IsValid(error)) return false;
  if (!pose.IsValid(error)) return false;
  if (!pen_dense.IsValid(error)) return false;
  if (!pen_shaft.IsValid(error)) return false;
  if (pen_rest_iterations < 0 || pen_rest_iterations > 50)
    return fail("pen_rest_iterations must be in [0, 50]");
  if (!(pen_rest_motion_px >= 0) || !(pen_rest_gap_s >= 0))
    return fail("pen_rest_motion_px and pen_rest_gap_s must be >= 0");
  if (!smoothing.IsValid(error)) return false;
  if (!pen_hypotheses.IsValid(error)) return false;
  if (!roi.IsValid(error)) return false;
  if (!(max_rmse_px > 0)) return fail("max_rmse_px must be positive");
  if (!(max_single_tag_rmse_cells > 0))
    return fail("max_single_tag_rmse_cells must be positive");
  if (!smoothing.reset_when_ambiguous &&
      smoothing.pen.reset_rotation_deg > flip_angle_deg)
    return fail(
        "smoothing an ambiguous pen needs its reset bound within "
        "flip_angle_deg");
  if (!(flip_angle_deg > 0 && flip_angle_deg < 180))
    return fail("flip_angle_deg must be in (0, 180)");
  if (!(ambiguity_margin_px >= 0))
    return fail("ambiguity_margin_px must be >= 0");
  if (!(flip_keep_rmse_px >= 0)) return fail("flip_keep_rmse_px must be >= 0");
  if (!(flip_cost_ratio > 0 && flip_cost_ratio <= 1))
    return fail("flip_cost_ratio must be in (0, 1]");
  if (!(cut_jump_fraction > 0)) return fail("cut_jump_fraction must be > 0");
  if (!(pen_shaft_resolve_ratio >= 0 && pen_shaft_resolve_ratio < 1))
    return fail("pen_shaft_resolve_ratio must be in [0, 1)");
  if (!(pen_shaft_turn_ratio >= 0 && pen_shaft_turn_ratio < 1))
    return fail("pen_shaft_turn_ratio must be in [0, 1)");
  if (!(tank_hold_s >= 0 && pen_hold_s >= 0))
    return fail("hold times must be >= 0");
  return true;
}

Tracker::Tracker(const Camera& camera, const Rig& rig,
                 const TrackerOptions& options)
    : camera_(camera),
      rig_(rig),
      options_(WithRigFamily(options, rig)),
      detector_(ValidDetectorOptions(options_, camera)),
      roi_search_(options_.roi) {
  std::string error;
  RIPPLE_CHECK(camera.IsValid(&error), "Tracker: invalid camera: " + error);
  RIPPLE_CHECK(rig.IsValid(&error), "Tracker: invalid rig: " + error);
  const auto family = TagFamily::Create(rig_.family);
  RIPPLE_CHECK(family != nullptr,
               "Tracker: invalid rig: unknown tag family " + rig_.family);
  cells_across_tag_ = family->width_at_border();
  if (rig_.pen && options_.pen_dense.enabled) {
    pen_dense_model_ = DenseTagModel::Create(*family, rig_.pen->faces,
                                             options_.pen_dense, &error);
    RIPPLE_CHECK(pen_dense_model_.has_value(),
                 "Tracker: invalid rig: " + error);
  }
  Reset();
}

void Tracker::Reset() {
  tank_ = ObjectState{};
  pen_ = ObjectState{};
  tank_.filter = PoseFilter(options_.smoothing.tank);
  if (rig_.pen)
    pen_.filter = PoseFilter(options_.smoothing.pen, rig_.pen->tip_in_pen);
  roi_search_.Reset();
  frame_ = 0;
  last_corners_.clear();
  last_corners_time_s_.reset();
}

bool Tracker::IsCut(const std::vector<TagDetection>& detections) const {
  if (last_corners_.empty() || detections.empty()) return false;
  int shared = 0, jumped = 0;
  for (const TagDetection& d : detections) {
    auto it = last_corners_.find(d.id);
    if (it == last_corners_.end()) continue;
    ++shared;
    double move = 0;
    for (int k = 0; k < 4; ++k) move += (d.corners[k] - it->second[k]).norm();
    if (0.25 * move > options_.cut_jump_fraction * d.SizePx()) ++jumped;
  }
  return shared == 0 || jumped == shared;
}

bool Tracker::Reportable(const std::vector<TagObservation>& obs,
                         const ObjectPose& pose) const {
  if (pose.rmse_px > options_.max_rmse_px) return false;
  // Three corners fit a pose exactly whatever their noise: nothing checks it.
  int corners = 0;
  for (const TagObservation& o : obs)
    corners += static_cast<int>(
        std::count(o.occluded.begin(), o.occluded.end(), false));
  if (corners < 4) return false;
  if (pose.tag_ids.size() != 1) return true;
  for (const TagObservation& o : obs) {
    if (o.id != pose.tag_ids[0]) continue;
    const double cell_px = o.size_px / cells_across_tag_;
    return pose.rmse_px <= options_.max_single_tag_rmse_cells * cell_px;
  }
  return true;
}

std::optional<Tracker::Estimate> Tracker::CheckFlip(
    const std::vector<TagObservation>& obs, const ObjectPose& estimate,
    const std::optional<Pose>& prior) const {
  Estimate e;
  e.pose = estimate;
  if (!prior) return e;
  if (RotationDistance(estimate.cam_from_object, *prior) <=
      options_.flip_angle_deg * kDegToRad)
    return e;
  ObjectPose continued;
  if (RefineObjectPose(options_.pose, camera_, obs, *prior, &continued) &&
      continued.rmse_px <= options_.max_rmse_px &&
      (continued.rmse_px <= options_.flip_keep_rmse_px ||
       !(estimate.sse_px2 < options_.flip_cost_ratio * continued.sse_px2))) {
    const bool different =
        RotationDistance(continued.cam_from_object, estimate.cam_from_object) >
        options_.flip_angle_deg * kDegToRad;
    continued.alternative_rmse_px = estimate.rmse_px;
    Estimate kept;
    kept.pose = continued;
    kept.flip_rejected = different;
    return kept;
  }
  e.jumped = true;
  return e;
}

void Tracker::TrackHypotheses(const std::vector<TagObservation>& obs,
                              bool use_prior, double time_s,
                              Estimate* e) const {
  const PenHypothesisInputs in{camera_,
                               options_.pose,
                               options_.max_rmse_px,
                               options_.flip_angle_deg,
                               options_.flip_keep_rmse_px,
                               options_.ambiguity_margin_px,
                               pen_.last_raw,
                               pen_.lost_raw,
                               pen_.last_seen_s,
                               pen_.hypotheses};
  TrackPenHypotheses(options_.pen_hypotheses, in, obs, use_prior, time_s,
                     &e->pose, &e->flip_rejected, &e->jumped, &e->hypotheses);
}

int Tracker::ShaftEdgesNeeded() const {
  return std::max((options_.pen_shaft.samples_per_side + 1) / 2, 1);
}

void Tracker::ResolveByShaft(const cv::Mat& gray,
                             const std::vector<TagObservation>& obs,
                             Estimate* e) const {
  const Pose& other = *e->hypotheses.other;
  const int reported_edges = ShaftEdgeSupport(
      gray, camera_, *rig_.pen, options_.pen_shaft, e->pose.cam_from_object);
  const int other_edges =
      ShaftEdgeSupport(gray, camera_, *rig_.pen, options_.pen_shaft, other);
  const int need = ShaftEdgesNeeded();
  const double ratio = options_.pen_shaft_resolve_ratio;
  auto clear = [&](int winner, int loser) {
    return winner >= need && loser <= ratio * winner;
  };
  if (clear(other_edges, reported_edges)) {
    ObjectPose swapped;
    if (!RefineObjectPose(options_.pose, camera_, obs, other, &swapped) ||
        !Reportable(obs, swapped))
      return;
    e->pose = swapped;
  } else if (!clear(reported_edges, other_edges)) {
    return;
  }
  e->pose.alternative.reset();
  e->pose.alternative_rmse_px = std::numeric_limits<double>::infinity();
  e->hypotheses = PenHypotheses{};
  e->flip_rejected = false;
}

void Tracker::CheckTurnByShaft(const cv::Mat& gray,
                               const std::vector<TagObservation>& obs,
                               const Pose& last, Estimate* e) const {
  const double flip = options_.flip_angle_deg * kDegToRad;
  // The pose to keep: the corners' own minimum near the last pose, or,
  // where they slide from there to the estimate (one basin, its bottom
  // moved by biased corners), the last pose itself, for the dense and shaft
  // steps to refine.
  ObjectPose kept;
  if (!RefineObjectPose(options_.pose, camera_, obs, last, &kept) ||
      !Reportable(obs, kept) ||
      RotationDistance(kept.cam_from_object, e->pose.cam_from_object) <= flip) {
    kept = e->pose;
    kept.cam_from_object = last;
    int corners = 0;
    kept.sse_px2 = ReprojectionSse(camera_, obs, last, &corners);
    kept.rmse_px = std::sqrt(kept.sse_px2 / std::max(corners, 1));
    kept.iterations = 0;
    kept.alternative.reset();
  }
  const int need = ShaftEdgesNeeded();
  const int kept_edges = ShaftEdgeSupport(
      gray, camera_, *rig_.pen, options_.pen_shaft, kept.cam_from_object);
  if (kept_edges < need) return;
  const int turned_edges = ShaftEdgeSupport(
      gray, camera_, *rig_.pen, options_.pen_shaft, e->pose.cam_from_object);
  if (!(turned_edges < options_.pen_shaft_turn_ratio * kept_edges)) return;
  kept.alternative_rmse_px = e->pose.rmse_px;
  e->pose = kept;
  e->flip_rejected = true;
  e->jumped = false;
  e->hypotheses = PenHypotheses{};
}

std::optional<Tracker::Estimate> Tracker::EstimateTank(
    const std::vector<TagObservation>& obs, bool use_prior) const {
  ObjectPose pose;
  if (!EstimateObjectPose(options_.pose, camera_, obs, {}, &pose))
    return std::nullopt;
  auto e = CheckFlip(obs, pose, use_prior ? tank_.last_raw : std::nullopt);
  if (!e || !Reportable(obs, e->pose)) return std::nullopt;
  return e;
}

void Tracker::PreferPlausibleTip(const std::vector<TagObservation>& obs,
                                 const Pose& cam_from_tank,
                                 ObjectPose* pose) const {
  if (!pose->alternative ||
      pose->alternative_rmse_px > pose->rmse_px + options_.ambiguity_margin_px)
    return;
  const Pose tank_from_cam = cam_from_tank.Inverse();
  // Distance of the tip from where a tip can be: over the board, at most
  // 0.3 m above it, never below the table (metres).
  const Eigen::Vector3d lo(-0.5 * rig_.tank.size_x_m - 0.05,
                           -0.5 * rig_.tank.size_y_m - 0.05, -0.005);
  const Eigen::Vector3d hi(0.5 * rig_.tank.size_x_m + 0.05,
                           0.5 * rig_.tank.size_y_m + 0.05, 0.3);
  auto outside = [&](const Pose& cam_from_pen) {
    const Eigen::Vector3d tip =
        tank_from_cam * (cam_from_pen * rig_.pen->tip_in_pen);
    return (tip.cwiseMax(lo).cwiseMin(hi) - tip).norm();
  };
  // Negative evidence: faces a branch shows nearly head-on (within 60
  // degrees) that were not detected count against it.
  auto missing = [&](const Pose& cam_from_pen) {
    int n = 0;
    for (const TagPlacement& face : rig_.pen->faces) {
      bool seen = false;
      for (const TagObservation& o : obs) seen = seen || o.id == face.id;
      if (!seen && FacingCosine(cam_from_pen, face.object_from_tag) > 0.5) ++n;
    }
    return n;
  };
  auto score = [&](const Pose& p) { return 10.0 * outside(p) + missing(p); };
  if (score(*pose->alternative) >= score(pose->cam_from_object)) return;
  ObjectPose other;
  if (!RefineObjectPose(options_.pose, camera_, obs, *pose->alternative,
                        &other))
    return;
  other.alternative = pose->cam_from_object;
  other.alternative_rmse_px = pose->rmse_px;
  *pose = other;
}

std::optional<Tracker::Estimate> Tracker::EstimatePen(
    const std::vector<TagObservation>& obs, bool use_prior,
    const std::optional<Pose>& cam_from_tank, double time_s) const {
  const std::optional<Pose> prior = use_prior ? pen_.last_raw : std::nullopt;
  const bool use_tip_prior =
      options_.pen_tip_prior && !prior && cam_from_tank.has_value();
  // Acquiring: keep the other branch of an ambiguous view however much
  // worse its IPPE start is, so that both can be followed.
  PoseEstimatorOptions acquire = options_.pose;
  if (options_.pen_hypotheses.enabled) acquire.ambiguity_ratio = 1e12;
  if (options_.pen_mode == PenMode::kJoint || obs.size() == 1) {
    ObjectPose pose;
    // Without refinement the branches alive follow this frame's IPPE pair.
    const bool both =
        !prior || (pen_.hypotheses.other && !options_.pose.refine);
    if (!EstimateObjectPose(both ? acquire : options_.pose, camera_, obs, {},
                            &pose))
      return std::nullopt;
    if (use_tip_prior) PreferPlausibleTip(obs, *cam_from_tank, &pose);
    auto e = CheckFlip(obs, pose, pen_.hypotheses.other ? std::nullopt : prior);
    if (e) TrackHypotheses(obs, use_prior, time_s, &*e);
    if (!e || !Reportable(obs, e->pose)) return std::nullopt;
    return e;
  }
  // Best face: pose every face alone, keep the best by the chosen rule.
  std::optional<Estimate> best;
  std::vector<TagObservation> best_obs;
  double best_score = std::numeric_limits<double>::infinity();
  for (const TagObservation& o : obs) {
    const std::vector<TagObservation> one = {o};
    ObjectPose pose;
    if (!EstimateObjectPose(options_.pose, camera_, one, {}, &pose)) continue;
    if (pose.rmse_px > options_.max_rmse_px) continue;
    double score;
    if (options_.face_selection == FaceSelection::kMostFrontal) {
      score = -std::abs(FacingCosine(pose.cam_from_object, o.object_from_tag));
    } else {
      score = PointUncertainty(camera_, one, pose.cam_from_object,
                               rig_.pen->tip_in_pen);
    }
    if (score < best_score) {
      best_score = score;
      best = Estimate();
      best->pose = pose;
      best_obs = one;
    }
  }
  if (!best) return std::nullopt;
  if (use_tip_prior) PreferPlausibleTip(best_obs, *cam_from_tank, &best->pose);
  auto e = CheckFlip(best_obs, best->pose,
                     pen_.hypotheses.other ? std::nullopt : prior);
  if (e) TrackHypotheses(best_obs, use_prior, time_s, &*e);
  if (!e || !Reportable(best_obs, e->pose)) return std::nullopt;
  return e;
}

void Tracker::UpdateObject(const std::optional<Estimate>& estimate,
                           double time_s, bool cut, double hold_s,
                           const std::pair<Pose, Pose>* tank_now,
                           ObjectState* state, ObjectTrack* out) {
  *out = ObjectTrack{};
  if (estimate) {
    const bool fresh = cut || !state->last_raw.has_value();
    if (cut || (fresh && !(time_s - state->last_seen_s <=
                           options_.smoothing.bridge_loss_s)))
      state->filter.Reset();
    out->status = TrackStatus::kTracked;
    out->rmse_px = estimate->pose.rmse_px;
    out->tags = estimate->pose.tag_ids;
    out->reinitialized = fresh;
    out->flip_rejected = estimate->flip_rejected;
    out->jumped = estimate->jumped && !cut;
    out->ambiguous = estimate->hypotheses.other.has_value();
    state->last_raw = estimate->pose.cam_from_object;
    state->lost_raw.reset();
    state->hypotheses = estimate->hypotheses;
    const Pose& raw = estimate->pose.cam_from_object;
    if (!options_.smoothing.enabled) {
      out->cam_from_object = raw;
    } else {
      const bool in_tank = tank_now != nullptr;
      const bool reset_ambiguous =
          out->ambiguous && options_.smoothing.reset_when_ambiguous;
      if (reset_ambiguous || out->jumped || in_tank != state->filter_in_tank)
        state->filter.Reset();
      state->filter_in_tank = in_tank;
      if (in_tank) {
        out->cam_from_object =
            tank_now->second *
            state->filter.Filter(tank_now->first.Inverse() * raw, time_s);
      } else {
        out->cam_from_object = state->filter.Filter(raw, time_s);
      }
      // While ambiguous the pose may switch branch: the next frame starts
      // afresh.
      if (reset_ambiguous) state->filter.Reset();
    }
    state->last_output = out->cam_from_object;
    state->last_seen_s = time_s;
    state->ever_seen = true;
    return;
  }
  if (state->last_output && !cut && time_s - state->last_seen_s <= hold_s) {
    out->status = TrackStatus::kHeld;
    out->cam_from_object = state->last_output;
    return;
  }
  if (state->last_raw) state->lost_raw = state->last_raw;
  if (cut) state->lost_raw.reset();
  state->last_raw.reset();
  state->last_output.reset();
  state->hypotheses.other.reset();
  // The filter outlives a short loss (SmoothingOptions::bridge_loss_s).
  if (cut) state->filter.Reset();
  out->status = TrackStatus::kLost;
}

bool Tracker::PenAtRest(const std::vector<TagObservation>& obs,
                        double time_s) const {
  if (obs.empty() || !last_corners_time_s_ ||
      !(time_s > *last_corners_time_s_) ||
      !(time_s - *last_corners_time_s_ <= options_.pen_rest_gap_s))
    return false;
  for (const TagObservation& o : obs) {
    const auto last = last_corners_.find(o.id);
    if (last == last_corners_.end()) return false;
    for (int k = 0; k < 4; ++k)
      if ((last->second[k] - o.pixels[k]).norm() > options_.pen_rest_motion_px)
        return false;
  }
  return true;
}

FrameResult Tracker::Update(const std::vector<TagDetection>& detections,
                            double time_s, const cv::Mat* gray) {
  FrameResult r;
  r.frame = frame_++;
  r.time_s = time_s;
  r.detections = detections;
  r.cut = IsCut(detections);
  const bool use_prior = !r.cut;
  const auto tank_obs = MatchObservations(camera_, rig_.tank_tags, detections);
  std::optional<Estimate> tank_estimate;
  if (!tank_obs.empty()) tank_estimate = EstimateTank(tank_obs, use_prior);
  UpdateObject(tank_estimate, time_s, r.cut, options_.tank_hold_s, nullptr,
               &tank_, &r.tank);
  if (rig_.pen) {
    const auto pen_obs =
        MatchObservations(camera_, rig_.pen->faces, detections);
    std::optional<Estimate> pen_estimate;
    if (!pen_obs.empty())
      pen_estimate =
          EstimatePen(pen_obs, use_prior, r.tank.cam_from_object, time_s);
    const double t_dense = NowMs();
    // The dense model's gain and offset are linear in light: sRGB-encoded
    // values are decoded first.
    const cv::Mat* dense_gray = gray;
    if (pen_estimate && gray &&
        (pen_dense_model_ || options_.pen_shaft.enabled) &&
        options_.detector.transfer != geometry::Transfer::kLinear) {
      if (decode_lut_.empty())
        decode_lut_ = DecodeToLinearLut(options_.detector.transfer);
      cv::LUT(*gray, decode_lut_, linear_gray_);
      dense_gray = &linear_gray_;
    }
    if (pen_estimate && pen_estimate->hypotheses.other && gray &&
        options_.pen_shaft.enabled && options_.pen_shaft_resolve_ratio > 0)
      ResolveByShaft(*dense_gray, pen_obs, &*pen_estimate);
    if (pen_estimate && use_prior && pen_.last_raw && gray &&
        options_.pen_shaft.enabled && options_.pen_shaft_turn_ratio > 0 &&
        RotationDistance(pen_estimate->pose.cam_from_object, *pen_.last_raw) >
            options_.flip_angle_deg * kDegToRad)
      CheckTurnByShaft(*dense_gray, pen_obs, *pen_.last_raw, &*pen_estimate);
    DenseRefineOptions dense_options = options_.pen_dense;
    if (pen_estimate && PenAtRest(pen_obs, time_s))
      dense_options.max_iterations =
          std::max(dense_options.max_iterations, options_.pen_rest_iterations);
    DenseRefineResult dense_result;
    const bool refined =
        pen_estimate && gray && pen_dense_model_ &&
        DenseRefinePose(*dense_gray, camera_, *pen_dense_model_, dense_options,
                        &pen_estimate->pose.cam_from_object, &dense_result);
    // The shaft's edges in linear light too: a symmetric blur leaves the
    // steepest point of a linear-light step where the step is. Its prior is
    // the pose it starts from: the dense step's where that refined it.
    const bool shaft_refined =
        pen_estimate && gray &&
        ShaftRefinePose(*dense_gray, camera_, *rig_.pen, pen_obs,
                        options_.pen_shaft, &pen_estimate->pose.cam_from_object,
                        nullptr,
                        refined && options_.pen_shaft.dense_prior
                            ? &dense_result.information
                            : nullptr);
    r.timings.dense_ms = NowMs() - t_dense;
    if (refined || shaft_refined) {
      int corners = 0;
      const double sse = ReprojectionSse(
          camera_, pen_obs, pen_estimate->pose.cam_from_object, &corners);
      pen_estimate->pose.rmse_px = std::sqrt(sse / std::max(corners, 1));
    }
    std::optional<std::pair<Pose, Pose>> tank_now;
    if (r.tank.status == TrackStatus::kTracked)
      tank_now.emplace(*tank_.last_raw, *r.tank.cam_from_object);
    UpdateObject(pen_estimate, time_s, r.cut, options_.pen_hold_s,
                 tank_now ? &*tank_now : nullptr, &pen_, &r.pen);
    if (r.tank.has_pose() && r.pen.has_pose()) {
      r.tip_in_tank = r.tank.cam_from_object->Inverse() *
                      (*r.pen.cam_from_object * rig_.pen->tip_in_pen);
    }
  }
  last_corners_.clear();
  for (const TagDetection& d : detections) last_corners_[d.id] = d.corners;
  last_corners_time_s_ = time_s;
  return r;
}

FrameResult Tracker::TrackDetections(
    const std::vector<TagDetection>& detections, double time_s,
    double detect_ms, const cv::Mat* gray) {
  const double t0 = NowMs();
  FrameResult r = Update(detections, time_s,
                         gray && gray->type() == CV_8UC1 ? gray : nullptr);
  r.timings.detect_ms = detect_ms;
  r.timings.pose_ms = NowMs() - t0;
  r.timings.total_ms = detect_ms + r.timings.pose_ms;
  r.timings.full_search = true;
  return r;
}

FrameResult Tracker::Track(const cv::Mat& image, double time_s) {
  const double t0 = NowMs();
  const cv::Mat* gray = &image;
  if (image.channels() == 3) {
    cv::cvtColor(image, gray_, cv::COLOR_BGR2GRAY);
    gray = &gray_;
  } else if (image.channels() == 4) {
    cv::cvtColor(image, gray_, cv::COLOR_BGRA2GRAY);
    gray = &gray_;
  }
  // Regions around each object's last pose, or around its pose before a
  // loss within roi.recent_loss_s.
  auto roi_object = [&](const ObjectState& state,
                        const std::vector<TagPlacement>& tags) {
    if (state.last_raw) return RoiObject{&*state.last_raw, &tags, false};
    if (state.lost_raw &&
        time_s - state.last_seen_s <= options_.roi.recent_loss_s)
      return RoiObject{&*state.lost_raw, &tags, true};
    return RoiObject{nullptr, &tags, false};
  };
  std::vector<RoiObject> objects = {roi_object(tank_, rig_.tank_tags)};
  if (rig_.pen) objects.push_back(roi_object(pen_, rig_.pen->faces));
  bool full = true;
  const std::vector<TagDetection> detections =
      roi_search_.Detect(&detector_, *gray, camera_, objects, &full);
  const double t1 = NowMs();
  FrameResult r = Update(detections, time_s, gray);
  const double t2 = NowMs();
  r.timings.detect_ms = t1 - t0;
  r.timings.pose_ms = t2 - t1;
  r.timings.total_ms = t2 - t0;
  r.timings.full_search = full;
  return r;
}

std::vector<PoseRow> Tracker::ToPoseRows(const FrameResult& result) const {
  std::vector<PoseRow> rows;
  auto make = [&](const char* name, const ObjectTrack& t) {
    PoseRow row;
    row.frame = result.frame;
    row.time_s = result.time_s;
    row.object = name;
    row.status = t.status;
    row.cam_from_object = t.cam_from_object;
    row.faces = t.tags;
    row.reproj_rmse_px = t.rmse_px;
    row.ms = result.timings.total_ms;
    return row;
  };
  rows.push_back(make("tank", result.tank));
  if (rig_.pen) {
    PoseRow row = make("pen", result.pen);
    row.tip_in_tank = result.tip_in_tank;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace ripple::tracking
