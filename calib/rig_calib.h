// Tag-layout calibration: bundle adjustment of where the tags really sit on
// one rigid object (the pen cube's faces or the tank board's tags) from many
// views in which several of them are seen together.
//
// Unknowns: cam_from_object for every used view, and object_from_tag for
// every tag except the reference, which stays at its nominal pose and so
// fixes the object frame (the gauge). Tag edges are the printed sizes and fix
// the scale. Residuals: the distorted-pixel error of every detected corner
// through the full lens model, with a Huber loss.
#ifndef RIPPLE_CALIB_RIG_CALIB_H_
#define RIPPLE_CALIB_RIG_CALIB_H_

#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/pose.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"

namespace ripple::calib {

using tracking::Pose;

struct RigCalibOptions {
  // Tag held at its nominal pose; -1 picks the tag seen in the most used
  // views (ties: the lowest id).
  int reference_id = -1;
  // A view is used when at least this many of the object's tags are seen in
  // it (one tag alone says nothing about the layout).
  int min_tags_per_view = 2;
  // Fewer used views than this is an error ("too few views").
  int min_views = 10;
  // A tag is refined only when it is seen in at least this many used views;
  // otherwise it keeps its nominal pose and is reported as not refined.
  int min_views_per_tag = 3;
  // A view whose initial pose (nominal layout) has a corner RMS above this
  // is dropped before the adjustment (a wrong detection or a bad branch).
  double max_initial_rmse_px = 8.0;
  // Tags stay in their nominal plane: only the in-plane translation and the
  // rotation about the tag normal are refined (3 degrees of freedom instead
  // of 6). Right for a flat printed board, where a hand-held video's narrow
  // baseline leaves the out-of-plane components poorly observed; wrong for
  // cube faces glued by hand.
  bool in_plane_only = false;
  double loss_scale_px = 1.0;  // Huber scale, pixels
  int max_iterations = 100;

  bool IsValid(std::string* error) const;
};

struct TagAdjustment {
  int id = -1;
  int views = 0;         // used views in which the tag is seen
  bool refined = false;  // false: the reference or too rarely seen
  Pose nominal;          // object_from_tag before
  Pose calibrated;       // object_from_tag after
  double moved_m = 0;    // |translation change|, metres
  double rotated_rad = 0;
};

struct RigCalibSummary {
  int views_total = 0;  // views given
  int views_used = 0;   // views with >= min_tags_per_view tags, kept
  int reference_id = -1;
  int num_corners = 0;
  // Corner RMS (pixels) with the nominal layout (view poses fitted to it)
  // and after the adjustment.
  double rms_before_px = 0;
  double rms_after_px = 0;
  int iterations = 0;
  bool converged = false;
  std::vector<TagAdjustment> tags;  // ascending id
  std::string BriefReport() const;
};

// Refines `nominal` (the object's tag placements) from per-view detections
// (ids not in `nominal` are ignored). On success fills `calibrated` (same
// order as `nominal`) and `summary`. False with `error` on too few views, no
// tag of the object found, or an unknown reference id.
bool CalibrateTagLayout(
    const RigCalibOptions& options, const tracking::Camera& camera,
    const std::vector<tracking::TagPlacement>& nominal,
    const std::vector<std::vector<tracking::TagDetection>>& detections_per_view,
    std::vector<tracking::TagPlacement>* calibrated, RigCalibSummary* summary,
    std::string* error);

// The two tag layouts of a rig that `ripple calib rig` can refine.
enum class LayoutObject { kTank, kPen };

// Views (entries of `detections_per_view`) in which at least two of `tags`
// are detected together: the views a layout adjustment can use.
int ViewsWithTwoTags(const std::vector<tracking::TagPlacement>& tags,
                     const std::vector<std::vector<tracking::TagDetection>>&
                         detections_per_view);

// The layout a recording was made for: the pen's cube faces when the rig has
// a pen and its faces are seen together at least as often as the board's
// tags, else the board.
LayoutObject ChooseLayoutObject(
    const tracking::Rig& rig,
    const std::vector<std::vector<tracking::TagDetection>>&
        detections_per_view);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_RIG_CALIB_H_
