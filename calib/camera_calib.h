// Camera intrinsics from views of a planar target: a chessboard, or the tags
// of a rig's tank board (any flat tag layout, e.g. the printed board sheet).
// Views pass through a ViewSelector that drops blurred and duplicate views;
// the accepted views go to OpenCV's calibrateCamera (Zhang's method with
// Levenberg-Marquardt refinement), with one round of rejection of views
// whose error is far above the others'.
//
// The lens distortion model is chosen from the data by K-fold
// cross-validation over views: each candidate is fitted without one fold of
// views, each held-out view's pose is fitted alone (solvePnP) with those
// intrinsics, and its points' reprojection error scores the model. Held-out
// views rather than an information criterion: the views' residuals are not
// independent Gaussian noise (corner detection errors are correlated along
// the board and the fitted poses absorb part of them), which the likelihood
// behind AIC/BIC assumes, while held-out error measures directly what a lens
// model is for, predicting where points fall in views it was not fitted to.
// The choice is the simplest model whose held-out mean squared error is
// within one standard error (over views) of the lowest (the
// one-standard-error rule, Hastie, Tibshirani & Friedman, "The Elements of
// Statistical Learning", 2nd ed., section 7.10): with k3 = 0 in the lens the
// richer models gain nothing beyond noise and the simpler one stays.
#ifndef RIPPLE_CALIB_CAMERA_CALIB_H_
#define RIPPLE_CALIB_CAMERA_CALIB_H_

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core.hpp>
#include <optional>
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

// OpenCV's lens distortion models, simplest first: Brown-Conrady radial
// (k1, k2, k3) and tangential (p1, p2) terms, and the rational radial model
// (k4..k6 in the denominator).
enum class DistortionModel {
  kAuto,      // chosen from the data (cross-validation over views)
  kK1K2,      // k1 k2 p1 p2, k3 = 0
  kK1K2K3,    // k1 k2 p1 p2 k3
  kRational,  // k1 k2 p1 p2 k3 k4 k5 k6
};
const char* ToString(DistortionModel model);  // auto, k1k2, k1k2k3, rational
std::optional<DistortionModel> ParseDistortionModel(const std::string& name);
// The fitted models, simplest first.
inline constexpr DistortionModel kDistortionCandidates[] = {
    DistortionModel::kK1K2, DistortionModel::kK1K2K3,
    DistortionModel::kRational};

struct CameraCalibOptions {
  int min_views = 10;  // fewer accepted views: "too few views"
  int max_views = 60;  // more are thinned evenly (calibration time)
  // The model to fit; kAuto picks one of kDistortionCandidates. Every
  // candidate is scored either way (CameraCalibSummary::models).
  DistortionModel distortion = DistortionModel::kAuto;
  int folds = 5;  // cross-validation folds over views (fewer views: one each)
  // After a first fit, views with an RMS above max(outlier_floor_px,
  // outlier_factor * median) are dropped and the fit repeated.
  double outlier_factor = 3.0;
  double outlier_floor_px = 1.0;

  bool IsValid(std::string* error) const;
};

// One distortion model's figures on the calibration's views.
struct DistortionScore {
  DistortionModel model = DistortionModel::kK1K2;
  bool ok = false;      // false: a fit failed (figures NaN)
  double rms_px = NAN;  // fitted to all used views
  // Cross-validated on views it was not fitted to: mean squared error per
  // point (px^2) and its standard error over views, and the RMS (px).
  double heldout_mse_px2 = NAN, heldout_mse_se_px2 = NAN;
  double heldout_rms_px = NAN;
  double fx = NAN, fy = NAN;  // fitted to all used views, pixels
};

struct CameraCalibSummary {
  DistortionModel model = DistortionModel::kK1K2;  // the one fitted
  bool model_chosen = false;          // by cross-validation (options: kAuto)
  double choice_limit_mse_px2 = NAN;  // the rule's bound, when chosen
  int folds = 0;
  std::vector<DistortionScore> models;  // kDistortionCandidates' order
  int views = 0;                        // used in the final fit
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
  // The distortion model lines alone: the choice and a table of the
  // candidates (also the camera file's comment).
  std::string ModelReport() const;
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
