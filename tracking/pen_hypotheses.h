// The two-hypothesis pen track. A square tag seen from some views has two
// poses that explain its corners almost equally well (IPPE's two branches);
// a pen acquired from such a view can start on the wrong one. When the pen
// is acquired (first frame, after a loss or a cut) from an ambiguous view (the
// other branch, refined, within the tracker's ambiguity_margin_px RMS and more
// than flip_angle_deg away), the other branch is kept alive next to the
// reported one. Every frame each is refined from its own last pose on the new
// corners (newly visible faces included) and carries a decaying sum of its
// squared errors (`decay` per frame). The reported branch changes only when
// the other's sum falls below `switch_ratio` times its own. The loser is
// dropped when its sum exceeds the winner's by 1 / resolve_ratio (after
// min_frames frames), at once when in one frame it fails (RMS above
// flip_keep_rmse_px) with 1 / resolve_ratio times the winner's error (e.g. a
// second face appeared) or exceeds max_rmse_px, or when the branches merge.
// While both are alive the track is ObjectTrack::ambiguous and the tracker's
// flip check is off, so flip rejection cannot lock a wrong branch in.
#ifndef RIPPLE_TRACKING_PEN_HYPOTHESES_H_
#define RIPPLE_TRACKING_PEN_HYPOTHESES_H_

#include <optional>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/object_pose.h"
#include "tracking/pose.h"

namespace ripple::tracking {

struct PenHypothesisOptions {
  // Off: a pen follows one branch, chosen at acquisition.
  bool enabled = true;
  double decay = 0.9;          // per-frame factor of the error sums, [0, 1]
  double switch_ratio = 0.5;   // (0, 1]
  double resolve_ratio = 0.1;  // (0, 1)
  // An ambiguous pen re-acquired within this long of being lost starts on
  // the branch nearer its last pose (seconds).
  double memory_s = 0.5;
  int min_frames = 5;  // frames both branches live before the sums decide

  bool IsValid(std::string* error) const;
};

// The other branch of an ambiguous view and the decaying sums of squared
// corner errors (pixels^2) of the reported branch and of it.
struct PenHypotheses {
  std::optional<Pose> other;  // cam_from_pen of the other branch
  double cost = 0;
  double other_cost = 0;
  int frames = 0;  // frames both branches have been alive
};

// What the tracker hands over for one frame. References are not owned and
// live for the call.
struct PenHypothesisInputs {
  const Camera& camera;
  const PoseEstimatorOptions& pose;
  // The tracker's limits (TrackerOptions): pixels, degrees.
  double max_rmse_px = 3.0;
  double flip_angle_deg = 10.0;
  double flip_keep_rmse_px = 1.0;
  double ambiguity_margin_px = 1.0;
  // The pen's history: the reported branch's last estimate (unset when
  // lost), the last estimate before the loss, when it was last seen
  // (seconds), and the branches alive after the last frame.
  const std::optional<Pose>& last_raw;
  const std::optional<Pose>& lost_raw;
  double last_seen_s = 0;
  const PenHypotheses& previous;
};

// Carries the two branches forward. `pose` is this frame's estimate from
// `obs` after the flip check (`flip_rejected`, `jumped` its flags);
// `use_prior` is false in a cut. Updates all three and fills `hypotheses`
// (left untouched when there is nothing to carry: then no other branch is
// alive).
void TrackPenHypotheses(const PenHypothesisOptions& options,
                        const PenHypothesisInputs& in,
                        const std::vector<TagObservation>& obs, bool use_prior,
                        double time_s, ObjectPose* pose, bool* flip_rejected,
                        bool* jumped, PenHypotheses* hypotheses);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_PEN_HYPOTHESES_H_
