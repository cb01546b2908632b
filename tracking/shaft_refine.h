// Refinement of the pen's pose by its shaft's silhouette.
//
// The tip lies on the shaft's axis, 14 cm from the cube. A cube face of 25
// pixels fixes the axis's direction to about a degree, which the lever arm
// turns into millimetres at the tip; the shaft itself, a 10 mm cylinder
// seen over a hundred pixels or more, fixes the image line of its axis far
// better. Each of its two silhouette lines is the trace of a plane through
// the camera centre tangent to the cylinder, so an edge pixel whose ray
// passes at the shaft's radius from the axis is explained exactly.
//
// The step samples points along the shaft's visible length, searches each
// side's edge along the predicted contour's normal (the strongest step of
// the side's common polarity, to a fraction of a pixel), keeps the edges on
// the straight line most of them lie on (a silhouette line is straight in
// undistorted coordinates), and moves the pose along the two motions the
// image line of the axis measures: a turn about the line of sight through
// the cube's centre and a shift across that line of sight and the shaft.
// Gauss-Newton on those two and the shaft's apparent radius, with the
// edges' tangency residuals (pixels, Huber) and, as the prior, the starting
// pose's information on the two motions: the dense step's where it refined
// the pose, else the corners' (J^T J over the detected corners, scaled by
// their noise). The rest (the distance, the tilt towards the
// camera, the roll about the shaft) stays where the corners and the dense
// step put it: the shaft's width and its change along the shaft measure
// those far worse (docs/tracking.md). The edges are searched once at the
// start and once more at the refined pose.
//
// The result is kept only when enough edges were found on both sides and
// it stays within a few degrees and millimetres of the start
// (ShaftRefineOptions).
#ifndef RIPPLE_TRACKING_SHAFT_REFINE_H_
#define RIPPLE_TRACKING_SHAFT_REFINE_H_

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/object_pose.h"
#include "tracking/pose.h"
#include "tracking/rig.h"

namespace ripple::tracking {

struct ShaftRefineOptions {
  bool enabled = true;
  int samples_per_side = 32;  // along the visible length
  // Shaft length left out at each end, metres: the cube's edge above, the
  // flat end (and its shadow) at the tip.
  double end_margin_m = 0.012;
  // The projected shaft must be at least this long (pixels), or the view is
  // along the axis and its lines say little.
  double min_length_px = 30.0;
  // Average each sample's profile over its stretch of the contour (about
  // one profile per pixel of it, at most 8), or read one profile through
  // the sample's point.
  bool average_along = true;
  // Edge search: this far either side of the predicted contour (pixels)...
  double search_px = 4.0;
  // ... for a step of at least this much (grey levels per pixel).
  double min_edge_dn = 10.0;
  // A side's edges farther than this (pixels) from the straight line most
  // of them lie on are left out.
  double line_tolerance_px = 0.6;
  // Samples found per side below which the step is skipped.
  int min_samples_per_side = 8;
  // Noise of an edge's position and of a corner's (pixels): their ratio
  // weighs the shaft against the starting pose.
  double edge_sigma_px = 0.3;
  double corner_sigma_px = 0.5;
  // The prior is the dense step's information where that step refined the
  // pose (the tracker reads this: it holds the dense step's result), else
  // the corners' at corner_sigma_px.
  bool dense_prior = true;
  // Weight of the dense step's information against the edges. That
  // information is J^T J over the final RMS residual: it counts 3 x 3
  // samples per cell as independent under a blur of a pixel or more, and
  // leaves out what the step's few iterations do not take from the start.
  // At 1 the pose's rotation is best, at 0.3 its tip (docs/tracking.md).
  double dense_information_scale = 0.3;
  double huber_px = 1.0;  // tangency residual where the loss turns robust
  // Fit the shaft's radius with the pose (its apparent width then leaves
  // the distance to the corners), or hold it at the rig's.
  bool free_radius = true;
  int iterations = 3;  // Gauss-Newton iterations per edge search
  // The refined pose must stay this close to the starting one.
  double max_rotation_deg = 3.0;
  double max_translation_m = 0.005;

  bool IsValid(std::string* error) const;
};

struct ShaftRefineResult {
  bool refined = false;   // the pose was replaced
  int edges[2] = {0, 0};  // edges used per side in the last search
  double rms_before_px = 0, rms_after_px = 0;  // tangency residuals
};

// Refines `cam_from_pen` in place on an 8-bit grey image (the camera's size;
// linear light keeps a blurred edge's steepest point where the edge is).
// `corners` are the pen's detected tags. The prior is the starting pose's
// information: `start_information` when given (the dense step's, in the
// perturbation R' = exp(omega) R, t' = t + v, scaled by
// dense_information_scale), else the corners' at corner_sigma_px.
// Returns true when the pose was replaced.
bool ShaftRefinePose(
    const cv::Mat& gray, const Camera& camera, const PenSpec& pen,
    const std::vector<TagObservation>& corners,
    const ShaftRefineOptions& options, Pose* cam_from_pen,
    ShaftRefineResult* result = nullptr,
    const Eigen::Matrix<double, 6, 6>* start_information = nullptr);

// How much of a shaft the image shows where `cam_from_pen` puts it: the
// edges ShaftRefinePose's search finds on each side's straight line (at the
// rig's radius, options.search_px either side), the fewer of the two sides.
// 0 when the shaft's image is shorter than min_length_px or the cube lies
// behind the camera. The two branches of an ambiguous single face put the
// shaft in different places, so this tells them apart where the face's
// corners cannot.
int ShaftEdgeSupport(const cv::Mat& gray, const Camera& camera,
                     const PenSpec& pen, const ShaftRefineOptions& options,
                     const Pose& cam_from_pen);

}  // namespace ripple::tracking

#endif  // RIPPLE_TRACKING_SHAFT_REFINE_H_
