// Error statistics of estimated poses against ground truth: the one
// definition of the error table of `ripple bench tracking` (the tracker and
// the baselines on synth's frames) and `ripple eval` (any two pose CSVs).
//
// Per frame: rotation (degrees) and translation (millimetres) error of the
// tank and the pen (cam_from_object), the pen tip's error in the tank frame
// (millimetres) and a flip (a rotation error over `flip_deg`). Over a
// sequence: median and p95 of each, flips, the share of frames with the
// object in view that the estimate reports as tracked, and the jitter on
// static segments.
//
// Static segments are found in the truth alone: runs of consecutive frames
// whose true pose stays within a tolerance of the run's first frame. Jitter
// is the spread of the estimate over those frames, pooled over segments
// (sum of squared deviations over sum of (n - 1)):
// - rotation: the angle of each estimate from the segment's mean rotation
//   (the normalised sum of sign-aligned quaternions, the chordal L2 mean of
//   Hartley et al., "Rotation Averaging", IJCV 2013);
// - tip: the distance of each estimated tip from the segment's mean tip,
//   i.e. the root of the summed per-axis variances (3-D, not per axis).
// The tank's segments need its true cam_from_tank static, the pen's its
// cam_from_pen, the tip's both (the tip in the tank frame is made of both
// estimates, so only then is its spread noise alone).
#ifndef RIPPLE_BENCH_POSE_ERRORS_H_
#define RIPPLE_BENCH_POSE_ERRORS_H_

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "tracking/pose.h"

namespace ripple::bench {

// The true poses of one frame.
struct TruthFrame {
  int frame = 0;
  tracking::Pose cam_from_tank;
  std::optional<tracking::Pose> cam_from_pen;  // absent: no pen in the scene
  std::optional<Eigen::Vector3d> tip_in_tank;  // metres, with cam_from_pen
  // Some of the object's tags are in view (tracked share's denominator).
  bool tank_visible = false, pen_visible = false;
};

// An estimate of one frame.
struct EstimateFrame {
  std::optional<tracking::Pose> cam_from_tank, cam_from_pen;
  std::optional<Eigen::Vector3d> tip_in_tank;  // metres
  // Reported as tracked (not held, not lost).
  bool tank_tracked = false, pen_tracked = false;
};

// Errors of one frame; NaN where the truth or the estimate lacks the
// quantity.
struct FrameErrors {
  double tank_rot_deg = NAN, tank_mm = NAN;
  double pen_rot_deg = NAN, pen_mm = NAN;
  double tip_mm = NAN;
  bool flip = false;
};

struct PoseErrorOptions {
  double flip_deg = 10;  // a rotation error above this is a flip, degrees
  // A frame belongs to a static run while its true pose is within these of
  // the run's first frame: far below the jitter worth reporting (0.1 mm,
  // 0.02 degrees), so that true motion inside a run adds at most ~1 % to it.
  double static_rotation_deg = 1e-3;
  double static_translation_m = 1e-5;
  int static_min_frames = 10;  // shorter runs are not static segments

  bool IsValid(std::string* error) const;
};

FrameErrors ComputeFrameErrors(const PoseErrorOptions& options,
                               const TruthFrame& truth,
                               const EstimateFrame& estimate);

// Frames [begin, end) of a sequence, as indices into its frames.
struct FrameRange {
  int begin = 0, end = 0;
};

// Spread of one quantity on the static segments.
struct Jitter {
  int segments = 0;  // static runs of the truth
  int samples = 0;   // estimates on them
  double std = NAN;  // degrees or millimetres; NaN below 2 samples a segment
};

struct ErrorSpread {
  double median = NAN, p95 = NAN;
};

struct PoseErrorSummary {
  int frames = 0;
  ErrorSpread tank_rot_deg, tank_mm, pen_rot_deg, pen_mm, tip_mm;
  int flips = 0;
  int tank_tracked = 0, tank_visible = 0, pen_tracked = 0, pen_visible = 0;
  Jitter tank_jitter_deg, pen_jitter_deg, tip_jitter_mm;
  std::vector<FrameRange> tank_static, pen_static, tip_static;

  // tracked / visible; NaN when the object was never in view.
  double tank_tracked_share() const;
  double pen_tracked_share() const;
};

// Collects a sequence frame by frame (in frame order) and summarises it.
class PoseErrorAccumulator {
 public:
  explicit PoseErrorAccumulator(const PoseErrorOptions& options = {});

  // Adds the next frame and returns its errors.
  FrameErrors Add(const TruthFrame& truth, const EstimateFrame& estimate);

  PoseErrorSummary Summarize() const;

  // Samples where the quantity exists, in frame order.
  const std::vector<double>& tank_rot_deg() const { return tank_rot_deg_; }
  const std::vector<double>& tip_mm() const { return tip_mm_; }
  const std::vector<FrameErrors>& frame_errors() const { return errors_; }
  int frames() const { return static_cast<int>(truth_.size()); }

 private:
  PoseErrorOptions options_;
  std::vector<TruthFrame> truth_;
  std::vector<EstimateFrame> estimates_;
  std::vector<FrameErrors> errors_;
  std::vector<double> tank_rot_deg_, tank_mm_, pen_rot_deg_, pen_mm_, tip_mm_;
};

// The error table's percentile `p` of `v`: rounded rank, NaN for an empty
// sample (a quantity never measured prints as nan).
double ErrorPercentile(const std::vector<double>& v, double p);

// The error table's columns (markdown), after the caller's own leading
// columns: the header cells, the separator cells and one row's cells, each
// starting with "| " and ending without the closing '|'.
std::string ErrorTableHeaderCells();
std::string ErrorTableSeparatorCells();
std::string ErrorTableCells(const PoseErrorSummary& summary);

// The summary's CSV columns (no leading or trailing comma).
std::string ErrorCsvHeader();
std::string ErrorCsvFields(const PoseErrorSummary& summary);

}  // namespace ripple::bench

#endif  // RIPPLE_BENCH_POSE_ERRORS_H_
