#include "tracking/pen_hypotheses.h"

#include <cmath>
#include <utility>

namespace ripple::tracking {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

bool PenHypothesisOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(decay >= 0 && decay <= 1))
    return fail("hypothesis decay must be in [0, 1]");
  if (!(resolve_ratio > 0 && resolve_ratio < 1))
    return fail("hypothesis resolve_ratio must be in (0, 1)");
  if (!(switch_ratio > 0 && switch_ratio <= 1))
    return fail("hypothesis switch_ratio must be in (0, 1]");
  if (!(memory_s >= 0)) return fail("hypothesis memory_s must be >= 0");
  if (min_frames < 1) return fail("hypothesis min_frames must be >= 1");
  return true;
}

void TrackPenHypotheses(const PenHypothesisOptions& options,
                        const PenHypothesisInputs& in,
                        const std::vector<TagObservation>& obs, bool use_prior,
                        double time_s, ObjectPose* pose, bool* flip_rejected,
                        bool* jumped, PenHypotheses* hypotheses) {
  if (!options.enabled) return;
  const double flip = in.flip_angle_deg * kDegToRad;
  auto fits = [&](const ObjectPose& p) { return p.rmse_px <= in.max_rmse_px; };
  if (use_prior && in.last_raw && in.previous.other) {
    // Both branches alive: refine each from its own last pose. Without
    // refinement, each follows the nearest of this frame's two IPPE branches.
    const std::vector<Pose> fresh =
        pose->alternative
            ? std::vector<Pose>{pose->cam_from_object, *pose->alternative}
            : std::vector<Pose>{pose->cam_from_object};
    auto follow = [&](const Pose& from, ObjectPose* out) {
      if (in.pose.refine)
        return RefineObjectPose(in.pose, in.camera, obs, from, out) &&
               fits(*out);
      const Pose* nearest = nullptr;
      for (const Pose& p : fresh)
        if (RotationDistance(p, from) <= flip &&
            (!nearest ||
             RotationDistance(p, from) < RotationDistance(*nearest, from)))
          nearest = &p;
      return nearest &&
             RefineObjectPose(in.pose, in.camera, obs, *nearest, out) &&
             fits(*out);
    };
    ObjectPose main, other;
    const bool main_ok = follow(*in.last_raw, &main);
    const bool other_ok = follow(*in.previous.other, &other);
    if (!main_ok && !other_ok) return;  // this frame's own estimate stands
    const double d = options.decay;
    double cost = d * in.previous.cost + main.sse_px2;
    double other_cost = d * in.previous.other_cost + other.sse_px2;
    const int frames = in.previous.frames + 1;
    // A decisive frame (e.g. a second face came into view): one branch fails
    // to explain the corners and the other does clearly better.
    const double resolve = options.resolve_ratio;
    auto beats = [&](const ObjectPose& a, const ObjectPose& b) {
      return b.rmse_px > in.flip_keep_rmse_px &&
             a.sse_px2 < resolve * b.sse_px2;
    };
    const bool decisive =
        main_ok && other_ok && (beats(main, other) || beats(other, main));
    // Reported: the branch reported so far until the other's error sum is
    // clearly lower (or the only one left, or the decisive winner).
    const bool swap =
        !main_ok || (decisive && beats(other, main)) ||
        (!decisive && other_ok && other_cost < options.switch_ratio * cost);
    if (swap) {
      std::swap(main, other);
      std::swap(cost, other_cost);
    }
    const bool other_alive =
        main_ok && other_ok && !decisive &&
        RotationDistance(main.cam_from_object, other.cam_from_object) > flip &&
        !(frames >= options.min_frames && cost < resolve * other_cost);
    *pose = main;
    *flip_rejected = false;
    *jumped = false;
    hypotheses->other.reset();
    hypotheses->cost = cost;
    hypotheses->other_cost = 0;
    hypotheses->frames = 0;
    if (other_alive) {
      pose->alternative = other.cam_from_object;
      pose->alternative_rmse_px = other.rmse_px;
      hypotheses->other = other.cam_from_object;
      hypotheses->other_cost = other_cost;
      hypotheses->frames = frames;
    }
    return;
  }
  // A new ambiguity: the pen is being acquired (first frame, after a loss or
  // a cut) and this frame's estimate came with a close other branch. A pen
  // already tracked keeps its branch by continuity (the flip check).
  const bool acquiring = !use_prior || !in.last_raw;
  if (!acquiring || *flip_rejected || !pose->alternative ||
      pose->alternative_rmse_px > pose->rmse_px + in.ambiguity_margin_px ||
      RotationDistance(*pose->alternative, pose->cam_from_object) <= flip)
    return;
  ObjectPose other;
  if (!RefineObjectPose(in.pose, in.camera, obs, *pose->alternative, &other) ||
      other.rmse_px > in.max_rmse_px)
    return;
  // Re-acquired shortly after a loss: report the branch nearer the last
  // pose (a pen does not turn by the gap between two branches while briefly
  // hidden).
  if (use_prior && !in.last_raw && in.lost_raw &&
      time_s - in.last_seen_s <= options.memory_s &&
      RotationDistance(other.cam_from_object, *in.lost_raw) <
          RotationDistance(pose->cam_from_object, *in.lost_raw)) {
    other.alternative = pose->cam_from_object;
    other.alternative_rmse_px = pose->rmse_px;
    std::swap(*pose, other);
  }
  hypotheses->other = other.cam_from_object;
  hypotheses->cost = pose->sse_px2;
  hypotheses->other_cost = other.sse_px2;
  hypotheses->frames = 1;
}

}  // namespace ripple::tracking
