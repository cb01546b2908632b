// Per-video tracking of the tank board and the pen cube: tag detection (with
// region search near the last poses), per-object pose, flip rejection, cut
// re-initialisation, held/lost status and optional smoothing.
//
// Driving it, one call per frame:
//
//   tracking::Tracker tracker(camera, rig, tracking::TrackerOptions{});
//   while (source.Read(&image, &time_s)) {
//     const tracking::FrameResult r = tracker.Track(image, time_s);
//     if (r.tank.has_pose()) DrawWater(*r.tank.cam_from_object);
//     if (r.tip_in_tank) Poke(*r.tip_in_tank);
//   }
//
// A cam_from_object is present exactly when the status is kTracked or kHeld:
// a lost object never carries an invented pose.
#ifndef RIPPLE_TRACKING_TRACKER_H_
#define RIPPLE_TRACKING_TRACKER_H_

#include <Eigen/Core>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "tracking/camera.h"
#include "tracking/dense_refine.h"
#include "tracking/object_pose.h"
#include "tracking/pen_hypotheses.h"
#include "tracking/pose.h"
#include "tracking/pose_csv.h"
#include "tracking/pose_filter.h"
#include "tracking/rig.h"
#include "tracking/roi_search.h"
#include "tracking/shaft_refine.h"
#include "tracking/tag_detector.h"
#include "tracking/track_result.h"

namespace ripple::tracking {

// How the pen pose is computed from its visible faces.
enum class PenMode {
  kJoint,     // all visible faces in one problem
  kBestFace,  // one face, chosen by FaceSelection
};
enum class FaceSelection {
  // The face whose single-face pose puts the least uncertainty on the pen
  // tip (Gauss-Newton covariance, TrackerOptions' docs).
  kLeastUncertain,
  // The face most nearly facing the camera (the paper's rule; the most
  // ambiguous view of a square).
  kMostFrontal,
};
const char* ToString(PenMode mode);
const char* ToString(FaceSelection selection);
std::optional<PenMode> ParsePenMode(const std::string& s);  // joint, best-face
std::optional<FaceSelection> ParseFaceSelection(
    const std::string& s);  // uncertainty, frontal

// One Euro smoothing of the reported poses. The tank is filtered in the
// camera frame; the pen relative to the tank (its tip the filtered point)
// while the tank is tracked, so that the tank's filter never lags the tip,
// and in the camera frame otherwise. A filter restarts on a cut, a loss
// longer than bridge_loss_s, a taken jump, when the pen's reference frame
// changes, on a jump beyond its reset bounds, and (reset_when_ambiguous)
// while the pen is ambiguous.
struct SmoothingOptions {
  bool enabled = true;
  // An object found again within this many seconds of its last pose goes on
  // through its filter (seconds, >= 0): a pen at rest that drops out of
  // detection for a few frames comes back smoothed, and the filter's reset
  // bounds still restart it if it moved meanwhile.
  double bridge_loss_s = 0.5;
  // Restart the pen's filter on every frame where it is ambiguous. Without
  // it a switch of branch still restarts it: the branches are more than
  // flip_angle_deg apart, beyond the pen filter's reset_rotation_deg.
  bool reset_when_ambiguous = false;
  PoseFilterOptions tank = DefaultTankFilter();
  PoseFilterOptions pen = DefaultPenFilter();

  static PoseFilterOptions DefaultTankFilter();
  static PoseFilterOptions DefaultPenFilter();
  bool IsValid(std::string* error) const;
};

struct TrackerOptions {
  // The family is taken from the rig; this one is ignored.
  TagDetectorOptions detector;
  PoseEstimatorOptions pose;
  PenMode pen_mode = PenMode::kJoint;
  FaceSelection face_selection = FaceSelection::kLeastUncertain;

  // A pose whose RMS reprojection error exceeds this is not reported
  // (pixels).
  double max_rmse_px = 3.0;
  // A pose from one tag explains six of its four corners' eight
  // coordinates; when the corners are the image of a square, the two left
  // over hold only their noise. Where a hand, the pen or the image's border
  // covers part of the tag's margin, libapriltag's outline follows the
  // occluder, and the corners stop being a square's: on synth's benchmark
  // preset most such views of a 23-33 px pen face read 0.145-0.29 cells RMS
  // and pose the tip 11-35 mm off, while nearly all uncovered ones read
  // 0.08 cells or less (docs/tracking.md, "A single tag that is not a
  // square"). A pose from a single tag whose RMS corner error exceeds this
  // many of the tag's cells (its mean edge in the image over the family's
  // width_at_border) is not reported.
  double max_single_tag_rmse_cells = 0.12;
  // Flips: an estimate whose rotation jumps by more than flip_angle_deg from
  // the previous frame's is checked against the pose refined from the
  // previous one (the continued pose). The jump is taken only when the
  // continued pose fails to explain the corners (RMS error above
  // flip_keep_rmse_px) and the jump's squared error is below flip_cost_ratio
  // times the continued pose's; otherwise the continued pose is used
  // (ObjectTrack::flip_rejected). Jumps taken are flagged (jumped).
  double flip_angle_deg = 10.0;
  double flip_keep_rmse_px = 1.0;
  double flip_cost_ratio = 0.5;
  // Cuts: when every tag seen in both frames moved by more than this fraction
  // of its own size (or no tag is shared), the video cut and every object is
  // re-initialised (no flip check, filters reset).
  double cut_jump_fraction = 0.5;
  // A pen acquired (first frame, after a loss or a cut) from an ambiguous
  // view takes the branch whose tip lies where a tip can be: over the board
  // (tank extent + 5 cm), not below the table, at most 0.3 m above it.
  bool pen_tip_prior = true;
  // Ambiguous means the other branch's RMS error is within this of the
  // chosen one's (pixels); it applies to the tip prior and to starting the
  // two-hypothesis pen track.
  double ambiguity_margin_px = 1.0;
  // The two-hypothesis pen track (tracking/pen_hypotheses.h).
  PenHypothesisOptions pen_hypotheses;
  // While both branches of an ambiguous pen are alive, its shaft decides
  // between them: the branch whose shaft the image shows (ShaftEdgeSupport:
  // edges for at least half of pen_shaft.samples_per_side on both sides) is
  // kept alone when the other's support is at most this share of it. Needs
  // the image and pen_shaft.enabled; 0: off.
  double pen_shaft_resolve_ratio = 0.25;
  // A pen whose pose turns by more than flip_angle_deg from the last frame's
  // (a jump the flip check takes, or the other branch of an ambiguous pen
  // taking over) keeps a pose near the last one instead (the corners'
  // minimum near it, or the last pose itself where the corners slide from
  // it to the turned one) when the shaft shows for that pose (edges for at
  // least half of
  // pen_shaft.samples_per_side on both sides) and the turned pose's support
  // is below this share of it: two small faces' corners can favour a pose
  // tens of degrees off whose shaft the image does not show. Continuity is
  // the prior here, so the margin is wider than pen_shaft_resolve_ratio's.
  // Needs the image and pen_shaft.enabled; 0: off.
  double pen_shaft_turn_ratio = 0.6;
  // How long an object that vanishes keeps its last pose as kHeld (seconds).
  double tank_hold_s = 0.5;
  double pen_hold_s = 0.0;

  // Region search around the tags predicted from the last poses
  // (tracking/roi_search.h).
  RoiSearchOptions roi;

  // Temporal smoothing of the reported poses (tracking/pose_filter.h).
  SmoothingOptions smoothing;

  // Dense photometric refinement of the pen's pose over its faces' known
  // look (tracking/dense_refine.h), after the corner-based estimate. Needs
  // the image: Track() applies it, TrackDetections() when given the grey
  // frame.
  DenseRefineOptions pen_dense;
  // Gauss-Newton iterations of the dense step on a pen at rest: when each
  // of its tags' detected corners lies within pen_rest_motion_px of the
  // same corner in the last frame (at most pen_rest_gap_s before). Without
  // motion blur the photometric optimum is unbiased, so iterating on takes
  // more of the corner pose's noise out; under motion blur an isotropic
  // template's optimum is biased, so a moving pen keeps
  // pen_dense.max_iterations (docs/tracking.md, "Iterating on a pen at
  // rest").
  int pen_rest_iterations = 3;
  double pen_rest_motion_px = 0.5;
  double pen_rest_gap_s = 0.1;

  // Refinement of the pen's pose by its shaft's silhouette edges
  // (tracking/shaft_refine.h), after the dense step; needs the image as the
  // dense step does.
  ShaftRefineOptions pen_shaft;

  bool IsValid(std::string* error) const;
};

class Tracker {
 public:
  // CHECKs camera, rig and options validity.
  Tracker(const Camera& camera, const Rig& rig, const TrackerOptions& options);

  // One frame (CV_8UC1 or CV_8UC3 BGR, the camera's size) at `time_s`
  // (seconds, increasing).
  FrameResult Track(const cv::Mat& image, double time_s);
  // Pose and temporal logic on detections made elsewhere (benchmarks feed
  // cached detections); no region search. detect_ms is taken as given. The
  // pen's dense refinement needs the frame's grey image (CV_8UC1); without
  // it the corner pose is reported.
  FrameResult TrackDetections(const std::vector<TagDetection>& detections,
                              double time_s, double detect_ms = 0,
                              const cv::Mat* gray = nullptr);
  // Forgets all history (a new video).
  void Reset();

  // Rows of the pose CSV for a frame (tank, then pen when the rig has one).
  std::vector<PoseRow> ToPoseRows(const FrameResult& result) const;

  const TrackerOptions& options() const { return options_; }
  const Camera& camera() const { return camera_; }
  const Rig& rig() const { return rig_; }

 private:
  struct ObjectState {
    std::optional<Pose> last_raw;     // last estimate, before smoothing
    std::optional<Pose> last_output;  // last reported pose
    double last_seen_s = 0;
    bool ever_seen = false;
    PoseFilter filter;
    bool filter_in_tank = false;   // pen: filtering tank_from_pen
    std::optional<Pose> lost_raw;  // last_raw when the object was lost
    // The other branch of an ambiguous view (pen only).
    PenHypotheses hypotheses;
  };
  struct Estimate {
    ObjectPose pose;
    bool flip_rejected = false;
    bool jumped = false;
    PenHypotheses hypotheses;  // to carry forward (pen only)
  };

  bool IsCut(const std::vector<TagDetection>& detections) const;
  // Whether the pen's detected corners `obs` lie where the last frame's
  // detections of the same tags did (TrackerOptions::pen_rest_motion_px).
  bool PenAtRest(const std::vector<TagObservation>& obs, double time_s) const;
  std::optional<Estimate> EstimateTank(const std::vector<TagObservation>& obs,
                                       bool use_prior) const;
  std::optional<Estimate> EstimatePen(const std::vector<TagObservation>& obs,
                                      bool use_prior,
                                      const std::optional<Pose>& cam_from_tank,
                                      double time_s) const;
  // Applies pen_tip_prior to an estimate made without a prior.
  void PreferPlausibleTip(const std::vector<TagObservation>& obs,
                          const Pose& cam_from_tank, ObjectPose* pose) const;
  // Carries the two branches of an ambiguous pen forward
  // (tracking/pen_hypotheses.h); `e` is this frame's estimate from `obs`,
  // after the flip check.
  void TrackHypotheses(const std::vector<TagObservation>& obs, bool use_prior,
                       double time_s, Estimate* e) const;
  // The shaft's edges (ShaftEdgeSupport) that show a pose's shaft: half of
  // pen_shaft.samples_per_side or more on both sides (a wrong pose's search
  // often picks up a few on a busy table or along a hand's fingers).
  int ShaftEdgesNeeded() const;
  // Keeps only the branch of an ambiguous pen whose shaft `gray` shows
  // (pen_shaft_resolve_ratio); leaves `e` as it is when neither is clear.
  void ResolveByShaft(const cv::Mat& gray,
                      const std::vector<TagObservation>& obs,
                      Estimate* e) const;
  // Keeps a pose near `last` (the last frame's pen) instead of the
  // estimate, turned from it by more than flip_angle_deg, where `gray`
  // shows the shaft of the first and not of the second
  // (pen_shaft_turn_ratio); the estimate is then flip_rejected.
  void CheckTurnByShaft(const cv::Mat& gray,
                        const std::vector<TagObservation>& obs,
                        const Pose& last, Estimate* e) const;
  // False when `pose` explains its corners worse than max_rmse_px, rests on
  // fewer than four corners (three fit a pose exactly whatever their errors,
  // so nothing checks it), or on one tag whose corners do not fit a square
  // (max_single_tag_rmse_cells).
  bool Reportable(const std::vector<TagObservation>& obs,
                  const ObjectPose& pose) const;
  std::optional<Estimate> CheckFlip(const std::vector<TagObservation>& obs,
                                    const ObjectPose& estimate,
                                    const std::optional<Pose>& prior) const;
  // `tank_now`: for the pen, this frame's raw and reported cam_from_tank
  // when the tank was tracked in it (the pen is then filtered relative to
  // it); null for the tank.
  void UpdateObject(const std::optional<Estimate>& estimate, double time_s,
                    bool cut, double hold_s,
                    const std::pair<Pose, Pose>* tank_now, ObjectState* state,
                    ObjectTrack* out);
  FrameResult Update(const std::vector<TagDetection>& detections, double time_s,
                     const cv::Mat* gray);

  Camera camera_;
  Rig rig_;
  TrackerOptions options_;
  TagDetector detector_;
  std::optional<DenseTagModel> pen_dense_model_;
  int cells_across_tag_ = 8;  // the rig family's width_at_border
  cv::Mat gray_;              // grey conversion of a colour frame
  // The detector's transfer decoded to linear 8-bit values for the dense
  // refinement (built on first use; empty for linear frames).
  cv::Mat decode_lut_, linear_gray_;
  ObjectState tank_;
  ObjectState pen_;
  RoiSearch roi_search_;
  int frame_ = 0;
  std::map<int, std::array<Eigen::Vector2d, 4>> last_corners_;
  std::optional<double> last_corners_time_s_;  // the frame they are from
};

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_TRACKER_H_
