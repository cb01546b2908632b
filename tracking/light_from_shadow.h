// The room light's dominant direction, and the share of the board's light
// that does not come from it, measured from the shadow the tracked pen
// casts on the board.
//
// Model. The board (the plane z = 0 of the tank frame) is lit by a distant
// light from the unit direction L (tank frame, towards the light, L_z > 0)
// and by ambient light from everywhere else. Where the pen hides the light
// the board keeps only the ambient part; with E_dir and E_amb the direct
// and ambient irradiance of the lit board,
//   shadowed / lit = E_amb / (E_amb + E_dir) = ambient share
// in the umbra, whatever the albedo: the ratio of a shadowed board point to
// lit board beside it (in linear light; frames are decoded with the
// camera's transfer) is the ambient share. The pen's shadow for a candidate
// L is the shaft (a cylinder of the pen's radius from the cube's -z face to
// the tip) and the cube projected along L onto the board,
//   S(X) = X_xy - (X_z / L_z) L_xy.
// Its shape pins L down: the shadow line's direction fixes the plane that
// holds the shaft's axis and L; where the line starts (the tip's shadow,
// h_tip cot(elevation) from the point under the tip) and where it ends (the
// cube's shadow, about h_cube cot(elevation) away) fix the elevation within
// that plane. The far end carries most of that: a low tip's shadow start
// moves by a millimetre or two over several degrees. So when the cube's
// shadow falls off the board, or the pen hides it, the elevation is weakly
// determined and `uncertainty_rad` says so; a light along the shaft casts
// no line and is not measured.
//
// Method, per frame:
//   1. the board inside `board_in_tank` is resampled on a grid of `texel_m`
//      in tank coordinates through camera.Project (lens distortion
//      included); texels outside the image or behind the pen's silhouette
//      (or `exclude`) are invalid; a texel holds its log linear brightness
//      and chromaticity, or those of frame / reference when a reference
//      image of the board is given (which removes the print's texture);
//   2. for a candidate L, samples along its predicted shadow's centre line
//      each measure a darkness: the mean of the two values just outside the
//      predicted shadow on either side, minus the mean of three values
//      across its umbra (the middle and just inside both edges, which pins
//      the line's lateral position). The lit reference is the brighter of
//      the sides that have the sample's colour (print only darkens; a
//      shadow keeps the board's colour, a hand does not); samples with
//      neither, and samples whose umbra points disagree by more than
//      `side_tolerance` (printed edges), are skipped. Inside the predicted
//      shadow the darkness should be -log(ambient share); in the stretches
//      beyond its two ends, 0;
//   3. each sample votes: inside the predicted shadow for the candidate
//      when dark, against it when lit; beyond the ends the other way round;
//      votes are bounded (so no printed ink outweighs a shadow), an umbra
//      that is not uniform across costs up to half a vote, and they are
//      summed (per length of board),
//      so the score loses both when the predicted shadow is too long (lit
//      board inside it) and when it is too short (shadow beyond its ends),
//      and grows with the length of shadow explained;
//   4. a coarse grid over the sphere of directions, then pattern search
//      from its best few local maxima down to `final_step_rad`; then a walk
//      along the ridge through the best (the lights in the plane of the
//      shaft's axis and the best cast the same line, only its ends move):
//      the estimate is the middle of the stretch that scores within a
//      tolerance of the top, so that a shadow whose ends are hidden is not
//      placed at one end of its range of explanations;
//   5. the estimate is accepted when its contrast (1 - shadow/lit, with the
//      ratio from the median darkness inside), its score and the share of
//      its inside samples that are dark pass the thresholds.
#ifndef RIPPLE_TRACKING_LIGHT_FROM_SHADOW_H_
#define RIPPLE_TRACKING_LIGHT_FROM_SHADOW_H_

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <deque>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"

namespace ripple::tracking {

struct LightFromShadowOptions {
  // Elevations searched, radians above the board plane (15 and 85 degrees):
  // below, the shadow runs off any board; above, it is a blob under the pen.
  double min_elevation_rad = 0.2618;
  double max_elevation_rad = 1.4835;
  // Grid step of the coarse search in azimuth and elevation, radians (3
  // degrees), and the step at which the refinement stops (0.1 degrees).
  double coarse_step_rad = 0.05236;
  double final_step_rad = 0.001745;
  // Local maxima of the coarse grid that are refined.
  int refine_seeds = 4;
  // Board resampling grid and the spacing of samples along the shadow line
  // (the coarse search uses twice this), metres.
  double texel_m = 0.001;
  double sample_step_m = 0.0015;
  // Lit reference samples sit this far outside the predicted shadow's edge
  // (plus the penumbra), metres.
  double side_gap_m = 0.003;
  // Umbra samples sit this far inside its edges (plus the penumbra): room
  // for blur and pose error, metres.
  double edge_margin_m = 0.0015;
  // Length of the stretches beyond the shadow's ends that must be lit,
  // metres.
  double end_length_m = 0.02;
  // Assumed angular radius of the light, radians (0.75 degrees: a 5 cm
  // lamp at 2 m): its penumbra is kept out of the samples.
  double light_radius_rad = 0.0131;
  // Samples whose umbra points differ by more than this (log brightness,
  // 0.35: 42%) straddle printed texture and are skipped.
  double side_tolerance = 0.35;
  // A shadow darkens the board without changing its colour (the ambient
  // light's colour is taken as the direct light's); samples whose
  // chromaticity (log B/G, log R/G) differs from the lit board's beside them
  // by more than this are something else in front of the board (a hand)
  // and are skipped. Raise it for ambient light of another colour (a blue
  // sky outside a window lit by a warm lamp).
  double chroma_tolerance = 0.2;
  // Darkness (log of lit / sample) at which a sample votes neither way
  // (0.25: a sample at 78% of the lit board); a full vote at twice it.
  double darkness_threshold = 0.25;
  // Pen silhouette grown by this much before its texels are dropped, pixels.
  double pen_grow_px = 2.0;
  // Acceptance: 1 - shadow/lit at least `min_contrast`; a score (net votes)
  // of at least `min_score`; at least `min_dark_fraction` of the samples
  // inside the shadow darker than the threshold; at least
  // `min_shadow_samples` samples inside it.
  double min_contrast = 0.12;
  double min_score = 12;
  double min_dark_fraction = 0.7;
  int min_shadow_samples = 12;
  // Step along the ridge (the lights casting the best's shadow line),
  // radians (0.5 degrees), and how far below the best a score may be and
  // still count as the top of the ridge: the larger of `ridge_tolerance`
  // votes and `ridge_tolerance_share` of the best.
  double ridge_step_rad = 0.008727;
  double ridge_tolerance = 1.5;
  double ridge_tolerance_share = 0.03;
  // `uncertainty_rad` reaches the directions of the coarse grid scoring at
  // least this share of the best.
  double uncertainty_score_share = 0.8;

  bool IsValid(std::string* error) const;
};

// A reference image of the board without shadows or occluders: the clean
// plate of tracking/clean_plate.h (CleanPlate::plate(), plate_origin_m(),
// texel_m()) or the printed design. 8-bit BGRA in the frame's encoding,
// alpha 255 where known; texel (column i, row j) has its centre at tank
// (x, y) = origin_m + texel_m * (i + 0.5, j + 0.5). Its gain relative to the
// frame does not matter (shadow and lit samples share it).
struct BoardReference {
  cv::Mat bgra;  // CV_8UC4
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  double texel_m = 0;
};

struct LightFromShadowInput {
  cv::Mat bgr;  // CV_8UC3, the camera's size, as captured
  Pose cam_from_tank;
  Pose tank_from_pen;  // the pen's tracked pose
  // Where the board may show the shadow (the printed sheet), tank frame,
  // metres.
  Eigen::AlignedBox2d board_in_tank;
  // Optional: the board without shadows (null: compare the shadow with the
  // board beside it in the frame alone).
  const BoardReference* reference = nullptr;
  // Optional: CV_8U of the camera's size, ideal-pinhole pixels (as
  // CleanPlate::foreground()): nonzero where something stands in front of
  // the board (hands); those texels are ignored.
  cv::Mat exclude;
};

enum class LightStatus {
  kFound,
  kBadInput,         // the frame's size or the board's pose does not fit
  kNoShadowOnBoard,  // no candidate's shadow has enough visible board
  kTooWeak,          // the best candidate is not dark or significant enough
};
const char* ToString(LightStatus status);

struct LightEstimate {
  LightStatus status = LightStatus::kNoShadowOnBoard;
  bool found() const { return status == LightStatus::kFound; }
  // The best candidate (also when not found, for diagnostics).
  Eigen::Vector3d light_in_tank = Eigen::Vector3d::UnitZ();  // unit
  double azimuth_rad = 0;    // atan2(L_y, L_x), tank frame, [0, 2 pi)
  double elevation_rad = 0;  // above the board plane
  // Shadowed / lit board brightness (linear light) and the ambient share
  // it measures (the same number: the model above).
  double shadow_ratio = 1;
  double ambient_share = 1;
  double contrast = 0;  // 1 - shadow_ratio
  // Net votes of the samples (step 3): a sample inside the predicted shadow
  // votes +1 when it is dark, -1 when lit, one beyond the shadow's ends the
  // other way round; linear in the darkness in between.
  double score = 0;
  double dark_fraction = 0;  // samples inside darker than the threshold
  // The larger of half the ridge's top (step 4) and the largest angle from
  // the estimate to a coarse-grid direction that scores at least
  // `uncertainty_score_share` of the best, radians.
  double uncertainty_rad = 0;
  // 0..1 (0 when not found): the score beyond its threshold (full at twice
  // it) times the uncertainty's (full at 3 degrees or less, none at 20
  // degrees or more).
  double confidence = 0;
  int shadow_samples = 0;  // samples inside the best candidate's shadow
  int end_samples = 0;     // samples in the stretches beyond its ends
  int candidates = 0;      // directions scored
};

// One frame. Returns estimate->found(); `options` must be valid.
bool EstimateLightFromShadow(const LightFromShadowOptions& options,
                             const Camera& camera, const PenSpec& pen,
                             const LightFromShadowInput& input,
                             LightEstimate* estimate);

// The predicted shadow's centre line for `light_in_tank` (unit, z > 0):
// the shadow of the tip and of the cube's centre, tank (x, y), metres.
// Shared by the estimator and its tests.
void PenShadowLine(const PenSpec& pen, const Pose& tank_from_pen,
                   const Eigen::Vector3d& light_in_tank,
                   Eigen::Vector2d* tip_shadow, Eigen::Vector2d* cube_shadow);

struct LightTrackerOptions {
  int window = 15;        // confident estimates kept
  int min_estimates = 3;  // before a light is reported
  double min_confidence = 0.3;
  // Estimates within this angle of the window's medoid are averaged into
  // the reported direction, radians (6 degrees).
  double inlier_angle_rad = 0.1047;
  // Frames without a confident estimate before the light is dropped (30 s
  // at 30 fps); 0 holds it for ever.
  int hold_frames = 900;

  bool IsValid(std::string* error) const;
};

// The light as held over frames.
struct TrackedLight {
  Eigen::Vector3d light_in_tank = Eigen::Vector3d::UnitZ();  // unit
  double ambient_share = 1;
  int estimates = 0;      // confident estimates in the window
  int inliers = 0;        // of them, within the inlier angle of the medoid
  double spread_rad = 0;  // median angle of the inliers to the direction
  int frames_since_estimate = 0;
};

// Holds the light over frames: the medoid of the last `window` confident
// estimates (the one with the least summed angle to the others, robust to
// a minority of wrong ones), refined by the mean of the estimates near it,
// and the median ambient share. A room's light is static, so frames
// without a shadow keep the last light for `hold_frames`. Not thread-safe.
class LightTracker {
 public:
  explicit LightTracker(
      const LightTrackerOptions& options = LightTrackerOptions());

  // One frame's estimate, found or not; returns the current light.
  const std::optional<TrackedLight>& Update(const LightEstimate& estimate);
  const std::optional<TrackedLight>& current() const { return current_; }
  // Forgets everything (a new room or light).
  void Reset();

 private:
  struct Entry {
    Eigen::Vector3d light_in_tank;
    double ambient_share;
  };
  void Recompute();

  LightTrackerOptions options_;
  std::deque<Entry> window_;
  std::optional<TrackedLight> current_;
  int frames_since_estimate_ = 0;
};

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_LIGHT_FROM_SHADOW_H_
