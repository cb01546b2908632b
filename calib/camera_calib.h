// Camera intrinsics from views of a planar target: a chessboard, or the tags
// of a rig's tank board (any flat tag layout, e.g. the printed board sheet).
// Views pass through a ViewSelector that drops blurred and duplicate views;
// the accepted views go to OpenCV's calibrateCamera (Zhang's method with
// Levenberg-Marquardt refinement), with one round of rejection of views
// whose error is far above the others'.
#ifndef RIPPLE_CALIB_CAMERA_CALIB_H_
#define RIPPLE_CALIB_CAMERA_CALIB_H_

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "tracking/camera.h"
#include "tracking/rig.h"
#include "tracking/tag_detector.h"

namespace ripple::calib {

// Points of a planar target seen in one image.
struct CalibView {
  int frame = -1;
  std::vector<int> point_ids;  // stable ids (chessboard index, 4 * tag + k)
  std::vector<Eigen::Vector3d> points_in_target;  // metres, z = 0
  std::vector<Eigen::Vector2d> pixels;  // distorted, OpenCV convention
  // Blur: median 10-90 % rise width of the target's edges, pixels (~0.8 for
  // a perfectly focused edge; grows with defocus and motion blur).
  double edge_width_px = 0;
};

// 10-90 % rise width (pixels) of the intensity profile of an 8-bit grey
// image along the segment a -> b, which should cross one dark-to-light edge.
// Negative when the profile has too little contrast to tell.
double EdgeRiseWidthPx(const cv::Mat& gray, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b);

// Chessboard with cols x rows inner corners and `square_m` squares; points
// in the board plane with the first corner at the origin. False when the
// board is not found completely.
bool DetectChessboardView(const cv::Mat& gray, int cols, int rows,
                          double square_m, CalibView* view);

// View of a planar tag target (`target_tags`, e.g. a rig's tank tags, all in
// the plane z = 0 of their object): every detected corner of every known
// tag. `border_cells` is the family's cells across the black square. False
// when fewer than `min_tags` of the target's tags were detected.
bool TagTargetView(const cv::Mat& gray,
                   const std::vector<tracking::TagPlacement>& target_tags,
                   const std::vector<tracking::TagDetection>& detections,
                   int border_cells, int min_tags, CalibView* view);

// True when every tag of `target_tags` lies in the plane z = 0.
bool IsPlanarTarget(const std::vector<tracking::TagPlacement>& target_tags);

struct ViewSelectionOptions {
  double max_edge_width_px = 3.5;  // blurrier views are rejected
  // A view whose points moved on average less than this fraction of the
  // image diagonal from an accepted view's (same points) is a duplicate.
  double min_change_fraction = 0.02;
};

// Accepts views one at a time, rejecting blurred ones and near-duplicates of
// views already accepted.
class ViewSelector {
 public:
  enum class Verdict { kAccepted, kBlurred, kDuplicate };
  ViewSelector(const ViewSelectionOptions& options, int width, int height);
  Verdict Offer(CalibView view);
  const std::vector<CalibView>& accepted() const { return accepted_; }
  int blurred() const { return blurred_; }
  int duplicates() const { return duplicates_; }

 private:
  ViewSelectionOptions options_;
  double diagonal_px_;
  std::vector<CalibView> accepted_;
  int blurred_ = 0, duplicates_ = 0;
};

struct CameraCalibOptions {
  int min_views = 10;     // fewer accepted views: "too few views"
  int max_views = 60;     // more are thinned evenly (calibration time)
  bool fix_k3 = true;     // k3 off (webcams rarely need it; it overfits)
  bool rational = false;  // k4..k6 on (wide-angle lenses)
  // After a first fit, views with an RMS above max(outlier_floor_px,
  // outlier_factor * median) are dropped and the fit repeated.
  double outlier_factor = 3.0;
  double outlier_floor_px = 1.0;

  bool IsValid(std::string* error) const;
};

struct CameraCalibSummary {
  int views = 0;                    // used in the final fit
  int views_dropped = 0;            // dropped as outliers after the first fit
  double rms_px = 0;                // over all points of the used views
  std::vector<int> frames;          // frame of each used view
  std::vector<double> view_rms_px;  // per used view
  // Share of an 8 x 6 grid of image cells holding at least one point, and
  // area of the convex hull of all points over the image area.
  double grid_coverage = 0;
  double hull_coverage = 0;
  // One-sigma uncertainty of fx, fy, cx, cy from OpenCV, pixels.
  double std_fx = 0, std_fy = 0, std_cx = 0, std_cy = 0;
  std::string BriefReport() const;
};

// Grid and hull coverage (see CameraCalibSummary) of a set of views.
void ViewCoverage(const std::vector<CalibView>& views, int width, int height,
                  double* grid_coverage, double* hull_coverage);

// Fits intrinsics and distortion. False with `error` on too few views or a
// failed fit.
bool CalibrateCamera(const CameraCalibOptions& options,
                     const std::vector<CalibView>& views, int width, int height,
                     tracking::Camera* camera, CameraCalibSummary* summary,
                     std::string* error);

}  // namespace ripple::calib

#endif  // RIPPLE_CALIB_CAMERA_CALIB_H_
