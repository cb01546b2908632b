#include "tracking/tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <opencv2/imgproc.hpp>

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

void Check(bool ok, const std::string& what, const std::string& error) {
  if (!ok) {
    std::fprintf(stderr, "Tracker: invalid %s: %s\n", what.c_str(),
                 error.c_str());
    std::abort();
  }
}

// Merges overlapping rectangles until none overlap.
std::vector<cv::Rect> MergeRects(std::vector<cv::Rect> rects) {
  bool merged = true;
  while (merged) {
    merged = false;
    for (size_t i = 0; i < rects.size() && !merged; ++i) {
      for (size_t j = i + 1; j < rects.size(); ++j) {
        if ((rects[i] & rects[j]).area() > 0) {
          rects[i] = rects[i] | rects[j];
          rects.erase(rects.begin() + j);
          merged = true;
          break;
        }
      }
    }
  }
  return rects;
}

// Viewing angle cosine of a face: 1 when it faces the camera squarely.
double FacingCosine(const Pose& cam_from_object, const Pose& object_from_tag) {
  const Pose cam_from_tag = cam_from_object * object_from_tag;
  const Eigen::Vector3d z = cam_from_tag.R().col(2);  // into the tag
  const Eigen::Vector3d ray = cam_from_tag.translation.normalized();
  return z.dot(ray);
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

bool TrackerOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!detector.IsValid(error)) return false;
  if (!pose.IsValid(error)) return false;
  if (!pen_dense.IsValid(error)) return false;
  if (!smoothing.IsValid(error)) return false;
  if (!(max_rmse_px > 0)) return fail("max_rmse_px must be positive");
  if (!(flip_angle_deg > 0 && flip_angle_deg < 180))
    return fail("flip_angle_deg must be in (0, 180)");
  if (!(hypothesis_decay >= 0 && hypothesis_decay <= 1))
    return fail("hypothesis_decay must be in [0, 1]");
  if (!(hypothesis_resolve_ratio > 0 && hypothesis_resolve_ratio < 1))
    return fail("hypothesis_resolve_ratio must be in (0, 1)");
  if (!(hypothesis_switch_ratio > 0 && hypothesis_switch_ratio <= 1))
    return fail("hypothesis_switch_ratio must be in (0, 1]");
  if (!(hypothesis_memory_s >= 0))
    return fail("hypothesis_memory_s must be >= 0");
  if (hypothesis_min_frames < 1)
    return fail("hypothesis_min_frames must be >= 1");
  if (!(ambiguity_margin_px >= 0))
    return fail("ambiguity_margin_px must be >= 0");
  if (!(flip_keep_rmse_px >= 0)) return fail("flip_keep_rmse_px must be >= 0");
  if (!(flip_cost_ratio > 0 && flip_cost_ratio <= 1))
    return fail("flip_cost_ratio must be in (0, 1]");
  if (!(cut_jump_fraction > 0)) return fail("cut_jump_fraction must be > 0");
  if (!(tank_hold_s >= 0 && pen_hold_s >= 0))
    return fail("hold times must be >= 0");
  if (full_search_period < 1) return fail("full_search_period must be >= 1");
  if (!(roi_margin_fraction >= 0 && roi_margin_px >= 0))
    return fail("roi margins must be >= 0");
  return true;
}

Tracker::Tracker(const Camera& camera, const Rig& rig,
                 const TrackerOptions& options)
    : camera_(camera),
      rig_(rig),
      options_(WithRigFamily(options, rig)),
      detector_((Check(options_.IsValid(nullptr), "options", ""),
                 options_.detector)) {
  std::string error;
  Check(camera.IsValid(&error), "camera", error);
  Check(rig.IsValid(&error), "rig", error);
  if (rig_.pen && options_.pen_dense.enabled) {
    const auto family = TagFamily::Create(rig_.family);
    Check(family != nullptr, "rig", "unknown tag family " + rig_.family);
    pen_dense_model_ = DenseTagModel::Create(*family, rig_.pen->faces,
                                             options_.pen_dense, &error);
    Check(pen_dense_model_.has_value(), "rig", error);
  }
  Reset();
}

void Tracker::Reset() {
  tank_ = ObjectState{};
  pen_ = ObjectState{};
  tank_.filter = PoseFilter(options_.smoothing);
  pen_.filter = PoseFilter(options_.smoothing);
  frame_ = 0;
  frames_since_full_ = 0;
  last_corners_.clear();
}

std::vector<cv::Rect> Tracker::PredictRois() const {
  std::vector<cv::Rect> rects;
  auto add_object = [&](const std::optional<Pose>& pose,
                        const std::vector<TagPlacement>& tags) {
    if (!pose) return;
    for (const TagPlacement& tag : tags) {
      // Skip faces turned well away from the camera.
      if (FacingCosine(*pose, tag.object_from_tag) < -0.2) continue;
      double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
      bool ok = true;
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d p = *pose * tag.CornerInObject(k);
        if (p.z() <= 1e-3) {
          ok = false;
          break;
        }
        const Eigen::Vector2d uv = camera_.Project(p);
        x0 = std::min(x0, uv.x());
        y0 = std::min(y0, uv.y());
        x1 = std::max(x1, uv.x());
        y1 = std::max(y1, uv.y());
      }
      if (!ok) continue;
      const double m =
          options_.roi_margin_fraction * std::max(x1 - x0, y1 - y0) +
          options_.roi_margin_px;
      x0 = std::max(x0 - m, -1.0);
      y0 = std::max(y0 - m, -1.0);
      x1 = std::min(x1 + m, double(camera_.width));
      y1 = std::min(y1 + m, double(camera_.height));
      if (x1 <= x0 || y1 <= y0) continue;
      const int ix0 = static_cast<int>(std::floor(x0)),
                iy0 = static_cast<int>(std::floor(y0));
      rects.emplace_back(ix0, iy0, static_cast<int>(std::ceil(x1)) - ix0,
                         static_cast<int>(std::ceil(y1)) - iy0);
    }
  };
  add_object(tank_.last_output, rig_.tank_tags);
  if (rig_.pen) add_object(pen_.last_output, rig_.pen->faces);
  return MergeRects(rects);
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
  if (!options_.pen_multi_hypothesis) return;
  const double flip = options_.flip_angle_deg * kDegToRad;
  auto fits = [&](const ObjectPose& p) {
    return p.rmse_px <= options_.max_rmse_px;
  };
  if (use_prior && pen_.last_raw && pen_.other_raw) {
    // Both branches alive: refine each from its own last pose. Without
    // refinement, each follows the nearest of this frame's two IPPE branches.
    const std::vector<Pose> fresh =
        e->pose.alternative
            ? std::vector<Pose>{e->pose.cam_from_object, *e->pose.alternative}
            : std::vector<Pose>{e->pose.cam_from_object};
    auto follow = [&](const Pose& from, ObjectPose* out) {
      if (options_.pose.refine)
        return RefineObjectPose(options_.pose, camera_, obs, from, out) &&
               fits(*out);
      const Pose* nearest = nullptr;
      for (const Pose& p : fresh)
        if (RotationDistance(p, from) <= flip &&
            (!nearest ||
             RotationDistance(p, from) < RotationDistance(*nearest, from)))
          nearest = &p;
      return nearest &&
             RefineObjectPose(options_.pose, camera_, obs, *nearest, out) &&
             fits(*out);
    };
    ObjectPose main, other;
    const bool main_ok = follow(*pen_.last_raw, &main);
    const bool other_ok = follow(*pen_.other_raw, &other);
    if (!main_ok && !other_ok) return;  // this frame's own estimate stands
    const double d = options_.hypothesis_decay;
    double cost = d * pen_.cost + main.sse_px2;
    double other_cost = d * pen_.other_cost + other.sse_px2;
    const int frames = pen_.hypothesis_frames + 1;
    // A decisive frame (e.g. a second face came into view): one branch fails
    // to explain the corners and the other does clearly better.
    const double resolve = options_.hypothesis_resolve_ratio;
    auto beats = [&](const ObjectPose& a, const ObjectPose& b) {
      return b.rmse_px > options_.flip_keep_rmse_px &&
             a.sse_px2 < resolve * b.sse_px2;
    };
    const bool decisive =
        main_ok && other_ok && (beats(main, other) || beats(other, main));
    // Reported: the branch reported so far until the other's error sum is
    // clearly lower (or the only one left, or the decisive winner).
    const bool swap = !main_ok || (decisive && beats(other, main)) ||
                      (!decisive && other_ok &&
                       other_cost < options_.hypothesis_switch_ratio * cost);
    if (swap) {
      std::swap(main, other);
      std::swap(cost, other_cost);
    }
    const bool other_alive =
        main_ok && other_ok && !decisive &&
        RotationDistance(main.cam_from_object, other.cam_from_object) > flip &&
        !(frames >= options_.hypothesis_min_frames &&
          cost < resolve * other_cost);
    e->pose = main;
    e->flip_rejected = false;
    e->jumped = false;
    e->other.reset();
    e->cost = cost;
    e->other_cost = 0;
    e->hypothesis_frames = 0;
    if (other_alive) {
      e->pose.alternative = other.cam_from_object;
      e->pose.alternative_rmse_px = other.rmse_px;
      e->other = other.cam_from_object;
      e->other_cost = other_cost;
      e->hypothesis_frames = frames;
    }
    return;
  }
  // A new ambiguity: the pen is being acquired (first frame, after a loss or
  // a cut) and this frame's estimate came with a close other branch. A pen
  // already tracked keeps its branch by continuity (the flip check).
  const bool acquiring = !use_prior || !pen_.last_raw;
  if (!acquiring || e->flip_rejected || !e->pose.alternative ||
      e->pose.alternative_rmse_px >
          e->pose.rmse_px + options_.ambiguity_margin_px ||
      RotationDistance(*e->pose.alternative, e->pose.cam_from_object) <= flip)
    return;
  ObjectPose other;
  if (!RefineObjectPose(options_.pose, camera_, obs, *e->pose.alternative,
                        &other) ||
      other.rmse_px > options_.max_rmse_px)
    return;
  // Re-acquired shortly after a loss: report the branch nearer the last
  // pose (a pen does not turn by the gap between two branches while briefly
  // hidden).
  if (use_prior && !pen_.last_raw && pen_.lost_raw &&
      time_s - pen_.last_seen_s <= options_.hypothesis_memory_s &&
      RotationDistance(other.cam_from_object, *pen_.lost_raw) <
          RotationDistance(e->pose.cam_from_object, *pen_.lost_raw)) {
    other.alternative = e->pose.cam_from_object;
    other.alternative_rmse_px = e->pose.rmse_px;
    std::swap(e->pose, other);
  }
  if (std::getenv("RIPPLE_HYP_DEBUG"))
    std::fprintf(stderr, "hyp start main %.3f (%.2f px) other %.3f (%.2f px)\n",
                 e->pose.sse_px2, e->pose.rmse_px, other.sse_px2,
                 other.rmse_px);
  e->other = other.cam_from_object;
  e->cost = e->pose.sse_px2;
  e->other_cost = other.sse_px2;
  e->hypothesis_frames = 1;
}

std::optional<Tracker::Estimate> Tracker::EstimateTank(
    const std::vector<TagObservation>& obs, bool use_prior) const {
  ObjectPose pose;
  if (!EstimateObjectPose(options_.pose, camera_, obs, {}, &pose))
    return std::nullopt;
  auto e = CheckFlip(obs, pose, use_prior ? tank_.last_raw : std::nullopt);
  if (!e || e->pose.rmse_px > options_.max_rmse_px) return std::nullopt;
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
  if (options_.pen_multi_hypothesis) acquire.ambiguity_ratio = 1e12;
  if (options_.pen_mode == PenMode::kJoint || obs.size() == 1) {
    ObjectPose pose;
    // Without refinement the branches alive follow this frame's IPPE pair.
    const bool both = !prior || (pen_.other_raw && !options_.pose.refine);
    if (!EstimateObjectPose(both ? acquire : options_.pose, camera_, obs, {},
                            &pose))
      return std::nullopt;
    if (use_tip_prior) PreferPlausibleTip(obs, *cam_from_tank, &pose);
    auto e = CheckFlip(obs, pose, pen_.other_raw ? std::nullopt : prior);
    if (e) TrackHypotheses(obs, use_prior, time_s, &*e);
    if (!e || e->pose.rmse_px > options_.max_rmse_px) return std::nullopt;
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
  auto e =
      CheckFlip(best_obs, best->pose, pen_.other_raw ? std::nullopt : prior);
  if (e) TrackHypotheses(best_obs, use_prior, time_s, &*e);
  if (!e || e->pose.rmse_px > options_.max_rmse_px) return std::nullopt;
  return e;
}

void Tracker::UpdateObject(const std::optional<Estimate>& estimate,
                           double time_s, bool cut, double hold_s,
                           ObjectState* state, ObjectTrack* out) {
  *out = ObjectTrack{};
  if (estimate) {
    const bool fresh = cut || !state->last_raw.has_value();
    if (fresh) state->filter.Reset();
    out->status = TrackStatus::kTracked;
    out->rmse_px = estimate->pose.rmse_px;
    out->tags = estimate->pose.tag_ids;
    out->reinitialized = fresh;
    out->flip_rejected = estimate->flip_rejected;
    out->jumped = estimate->jumped && !cut;
    out->ambiguous = estimate->other.has_value();
    state->last_raw = estimate->pose.cam_from_object;
    state->lost_raw.reset();
    state->other_raw = estimate->other;
    state->cost = estimate->cost;
    state->other_cost = estimate->other_cost;
    state->hypothesis_frames = estimate->hypothesis_frames;
    out->cam_from_object =
        state->filter.Filter(estimate->pose.cam_from_object, time_s);
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
  state->other_raw.reset();
  state->filter.Reset();
  out->status = TrackStatus::kLost;
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
  UpdateObject(tank_estimate, time_s, r.cut, options_.tank_hold_s, &tank_,
               &r.tank);
  if (rig_.pen) {
    const auto pen_obs =
        MatchObservations(camera_, rig_.pen->faces, detections);
    std::optional<Estimate> pen_estimate;
    if (!pen_obs.empty())
      pen_estimate =
          EstimatePen(pen_obs, use_prior, r.tank.cam_from_object, time_s);
    const double t_dense = NowMs();
    const bool refined =
        pen_estimate && gray && pen_dense_model_ &&
        DenseRefinePose(*gray, camera_, *pen_dense_model_, options_.pen_dense,
                        &pen_estimate->pose.cam_from_object);
    r.timings.dense_ms = NowMs() - t_dense;
    if (refined) {
      int corners = 0;
      const double sse = ReprojectionSse(
          camera_, pen_obs, pen_estimate->pose.cam_from_object, &corners);
      pen_estimate->pose.rmse_px = std::sqrt(sse / std::max(corners, 1));
    }
    UpdateObject(pen_estimate, time_s, r.cut, options_.pen_hold_s, &pen_,
                 &r.pen);
    if (r.tank.has_pose() && r.pen.has_pose()) {
      r.tip_in_tank = r.tank.cam_from_object->Inverse() *
                      (*r.pen.cam_from_object * rig_.pen->tip_in_pen);
    }
  }
  last_corners_.clear();
  for (const TagDetection& d : detections) last_corners_[d.id] = d.corners;
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
  const bool any_pose =
      tank_.last_output.has_value() || pen_.last_output.has_value();
  bool full = !options_.roi_search || !any_pose ||
              frames_since_full_ + 1 >= options_.full_search_period;
  std::vector<TagDetection> detections;
  if (!full) {
    const std::vector<cv::Rect> rois = PredictRois();
    if (rois.empty()) {
      full = true;
    } else {
      detections = detector_.Detect(*gray, rois);
      // Fall back to the whole frame when a tracked object went missing.
      auto found = [&](const std::vector<TagPlacement>& tags) {
        for (const TagDetection& d : detections)
          for (const TagPlacement& t : tags)
            if (t.id == d.id) return true;
        return false;
      };
      const bool tank_missing =
          tank_.last_output.has_value() && !found(rig_.tank_tags);
      const bool pen_missing =
          rig_.pen && pen_.last_output.has_value() && !found(rig_.pen->faces);
      if (tank_missing || pen_missing) full = true;
    }
  }
  if (full) {
    detections = detector_.Detect(*gray);
    frames_since_full_ = 0;
  } else {
    ++frames_since_full_;
  }
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
