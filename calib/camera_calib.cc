#include "calib/camera_calib.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace ripple::calib {
namespace {

double Bilinear(const cv::Mat& gray, double x, double y) {
  x = std::clamp(x, 0.0, gray.cols - 1.001);
  y = std::clamp(y, 0.0, gray.rows - 1.001);
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const uint8_t* r0 = gray.ptr<uint8_t>(y0);
  const uint8_t* r1 = gray.ptr<uint8_t>(std::min(y0 + 1, gray.rows - 1));
  const int x1 = std::min(x0 + 1, gray.cols - 1);
  return (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x1]) +
         fy * ((1 - fx) * r1[x0] + fx * r1[x1]);
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

double EdgeRiseWidthPx(const cv::Mat& gray, const Eigen::Vector2d& a,
                       const Eigen::Vector2d& b) {
  const double length = (b - a).norm();
  if (length < 2.0) return -1;
  const int n = std::max(16, static_cast<int>(std::ceil(length * 4)));
  const double step = length / (n - 1);
  std::vector<double> p(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d q = a + (b - a) * (double(i) / (n - 1));
    p[i] = Bilinear(gray, q.x(), q.y());
  }
  if (p.front() > p.back()) std::reverse(p.begin(), p.end());
  const double lo = *std::min_element(p.begin(), p.end());
  const double hi = *std::max_element(p.begin(), p.end());
  if (hi - lo < 20) return -1;
  const double l10 = lo + 0.1 * (hi - lo), l50 = lo + 0.5 * (hi - lo),
               l90 = lo + 0.9 * (hi - lo);
  int i50 = 0;
  while (i50 < n - 1 && p[i50] < l50) ++i50;
  // Walk out from the middle crossing to the 10 % and 90 % crossings, with
  // linear interpolation between samples.
  double x10 = 0, x90 = n - 1;
  for (int i = i50; i > 0; --i) {
    if (p[i - 1] <= l10) {
      x10 = (i - 1) + (l10 - p[i - 1]) / std::max(p[i] - p[i - 1], 1e-9);
      break;
    }
  }
  for (int i = i50; i < n - 1; ++i) {
    if (p[i + 1] >= l90) {
      x90 = i + (l90 - p[i]) / std::max(p[i + 1] - p[i], 1e-9);
      break;
    }
  }
  return std::max(0.0, x90 - x10) * step;
}

bool DetectChessboardView(const cv::Mat& gray, int cols, int rows,
                          double square_m, CalibView* view) {
  std::vector<cv::Point2f> corners;
  const cv::Size pattern(cols, rows);
  if (!cv::findChessboardCornersSB(gray, pattern, corners,
                                   cv::CALIB_CB_NORMALIZE_IMAGE |
                                       cv::CALIB_CB_EXHAUSTIVE |
                                       cv::CALIB_CB_ACCURACY))
    return false;
  if (static_cast<int>(corners.size()) != cols * rows) return false;
  *view = CalibView();
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const int i = r * cols + c;
      view->point_ids.push_back(i);
      view->points_in_target.emplace_back(c * square_m, r * square_m, 0.0);
      view->pixels.emplace_back(corners[i].x, corners[i].y);
    }
  }
  // Blur along the grid lines between neighbouring corners.
  std::vector<double> widths;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      for (int dir = 0; dir < 2; ++dir) {
        const int r2 = r + dir, c2 = c + 1 - dir;
        if (r2 >= rows || c2 >= cols) continue;
        const Eigen::Vector2d p = view->pixels[r * cols + c];
        const Eigen::Vector2d q = view->pixels[r2 * cols + c2];
        const Eigen::Vector2d mid = 0.5 * (p + q);
        const Eigen::Vector2d normal(-(q - p).y(), (q - p).x());
        const double w =
            EdgeRiseWidthPx(gray, mid - 0.4 * normal, mid + 0.4 * normal);
        if (w >= 0) widths.push_back(w);
      }
    }
  }
  view->edge_width_px = Median(widths);
  return true;
}

bool IsPlanarTarget(const std::vector<tracking::TagPlacement>& target_tags) {
  for (const auto& t : target_tags)
    for (int k = 0; k < 4; ++k)
      if (std::abs(t.CornerInObject(k).z()) > 1e-6) return false;
  return !target_tags.empty();
}

bool TagTargetView(const cv::Mat& gray,
                   const std::vector<tracking::TagPlacement>& target_tags,
                   const std::vector<tracking::TagDetection>& detections,
                   int border_cells, int min_tags, CalibView* view) {
  *view = CalibView();
  std::vector<double> widths;
  int tags = 0;
  for (const tracking::TagDetection& d : detections) {
    const tracking::TagPlacement* placement = nullptr;
    for (const auto& t : target_tags)
      if (t.id == d.id) placement = &t;
    if (!placement) continue;
    ++tags;
    for (int k = 0; k < 4; ++k) {
      view->point_ids.push_back(4 * d.id + k);
      view->points_in_target.push_back(placement->CornerInObject(k));
      view->pixels.push_back(d.corners[k]);
    }
    // Blur across each edge at its middle, from inside the black border to
    // the white margin (0.8 cell each way).
    const double cell = d.SizePx() / std::max(border_cells, 1);
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& c : d.corners) centre += 0.25 * c;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d p = d.corners[k], q = d.corners[(k + 1) % 4];
      const Eigen::Vector2d mid = 0.5 * (p + q);
      Eigen::Vector2d out(-(q - p).y(), (q - p).x());
      out.normalize();
      if (out.dot(mid - centre) < 0) out = -out;
      const double w =
          EdgeRiseWidthPx(gray, mid - 0.8 * cell * out, mid + 0.8 * cell * out);
      if (w >= 0) widths.push_back(w);
    }
  }
  view->edge_width_px = Median(widths);
  return tags >= min_tags && tags > 0;
}

ViewSelector::ViewSelector(const ViewSelectionOptions& options, int width,
                           int height)
    : options_(options), diagonal_px_(std::hypot(width, height)) {}

ViewSelector::Verdict ViewSelector::Offer(CalibView view) {
  if (view.edge_width_px > options_.max_edge_width_px) {
    ++blurred_;
    return Verdict::kBlurred;
  }
  const double min_change = options_.min_change_fraction * diagonal_px_;
  for (const CalibView& a : accepted_) {
    std::map<int, Eigen::Vector2d> prev;
    for (size_t i = 0; i < a.point_ids.size(); ++i)
      prev[a.point_ids[i]] = a.pixels[i];
    double sum = 0;
    int common = 0;
    for (size_t i = 0; i < view.point_ids.size(); ++i) {
      auto it = prev.find(view.point_ids[i]);
      if (it == prev.end()) continue;
      sum += (it->second - view.pixels[i]).norm();
      ++common;
    }
    // Same points (mostly) in about the same place.
    if (2 * common >= static_cast<int>(view.point_ids.size()) && common > 0 &&
        sum / common < min_change) {
      ++duplicates_;
      return Verdict::kDuplicate;
    }
  }
  accepted_.push_back(std::move(view));
  return Verdict::kAccepted;
}

const char* ToString(DistortionModel model) {
  switch (model) {
    case DistortionModel::kAuto:
      return "auto";
    case DistortionModel::kK1K2:
      return "k1k2";
    case DistortionModel::kK1K2K3:
      return "k1k2k3";
    case DistortionModel::kRational:
      return "rational";
  }
  return "?";
}

std::optional<DistortionModel> ParseDistortionModel(const std::string& name) {
  for (DistortionModel m :
       {DistortionModel::kAuto, DistortionModel::kK1K2,
        DistortionModel::kK1K2K3, DistortionModel::kRational})
    if (name == ToString(m)) return m;
  return std::nullopt;
}

bool CameraCalibOptions::IsValid(std::string* error) const {
  if (min_views < 3 || max_views < min_views) {
    if (error) *error = "need 3 <= min_views <= max_views";
    return false;
  }
  if (!(outlier_factor > 1) || !(outlier_floor_px > 0)) {
    if (error) *error = "outlier_factor must be > 1 and outlier_floor_px > 0";
    return false;
  }
  if (folds < 2) {
    if (error) *error = "folds must be >= 2";
    return false;
  }
  return true;
}

std::string CameraCalibSummary::ModelReport() const {
  std::string s;
  char line[256];
  std::snprintf(line, sizeof(line), "distortion model: %s (%s)\n",
                ToString(model),
                model_chosen ? (std::to_string(folds) +
                                "-fold held-out views, one-standard-error rule")
                                   .c_str()
                             : "forced");
  s += line;
  if (model_chosen) {
    std::snprintf(line, sizeof(line),
                  "  (the simplest model with held-out RMS <= %.3f px: the "
                  "lowest plus one standard error)\n",
                  std::sqrt(choice_limit_mse_px2));
    s += line;
  }
  s += "  model     RMS px  held-out px  fx       fy\n";
  for (const DistortionScore& m : models) {
    std::snprintf(line, sizeof(line), "  %-9s %6.3f  %11.3f  %7.2f  %7.2f%s\n",
                  ToString(m.model), m.rms_px, m.heldout_rms_px, m.fx, m.fy,
                  m.model == model ? "  <-" : (m.ok ? "" : "  (fit failed)"));
    s += line;
  }
  return s;
}

std::string CameraCalibSummary::BriefReport() const {
  std::string s;
  char line[256];
  std::snprintf(line, sizeof(line),
                "camera: %d views (%d dropped as outliers), RMS %.3f px\n"
                "coverage: %.0f %% of an 8x6 grid, convex hull %.0f %% of the "
                "image\n"
                "sigma: fx %.2f fy %.2f cx %.2f cy %.2f px\n",
                views, views_dropped, rms_px, 100 * grid_coverage,
                100 * hull_coverage, std_fx, std_fy, std_cx, std_cy);
  s += line;
  s += ModelReport();
  s += "per-view RMS (px):";
  for (size_t i = 0; i < view_rms_px.size(); ++i) {
    std::snprintf(line, sizeof(line), "%s frame %d: %.3f", i ? "," : "",
                  frames[i], view_rms_px[i]);
    s += line;
  }
  return s + "\n";
}

void ViewCoverage(const std::vector<CalibView>& views, int width, int height,
                  double* grid_coverage, double* hull_coverage) {
  constexpr int kCols = 8, kRows = 6;
  bool cell[kRows][kCols] = {};
  std::vector<cv::Point2f> all;
  for (const CalibView& v : views) {
    for (const Eigen::Vector2d& p : v.pixels) {
      const int c =
          std::clamp(static_cast<int>(p.x() * kCols / width), 0, kCols - 1);
      const int r =
          std::clamp(static_cast<int>(p.y() * kRows / height), 0, kRows - 1);
      cell[r][c] = true;
      all.emplace_back(p.x(), p.y());
    }
  }
  int filled = 0;
  for (auto& row : cell)
    for (bool b : row) filled += b;
  *grid_coverage = double(filled) / (kCols * kRows);
  *hull_coverage = 0;
  if (all.size() >= 3) {
    std::vector<cv::Point2f> hull;
    cv::convexHull(all, hull);
    *hull_coverage = cv::contourArea(hull) / (double(width) * height);
  }
}

namespace {

int CalibFlags(DistortionModel model) {
  switch (model) {
    case DistortionModel::kK1K2K3:
      return 0;
    case DistortionModel::kRational:
      return cv::CALIB_RATIONAL_MODEL;
    default:
      return cv::CALIB_FIX_K3;
  }
}

struct CvViews {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
};

CvViews ToCv(const std::vector<CalibView>& views) {
  CvViews out;
  for (const CalibView& v : views) {
    out.object.emplace_back();
    out.image.emplace_back();
    for (size_t i = 0; i < v.pixels.size(); ++i) {
      out.object.back().emplace_back(v.points_in_target[i].x(),
                                     v.points_in_target[i].y(), 0.f);
      out.image.back().emplace_back(v.pixels[i].x(), v.pixels[i].y());
    }
  }
  return out;
}

struct ModelFit {
  cv::Mat k, d, std_intrinsics;
  std::vector<double> view_rms;
  double rms = 0;
};

const cv::TermCriteria kCalibTermination(cv::TermCriteria::COUNT +
                                             cv::TermCriteria::EPS,
                                         100, 1e-12);

// Starting at the full fit, the folds' fits converge in a few iterations;
// the cap keeps a fold that does not (a poorly constrained rational model)
// from costing the full fit's 100.
const cv::TermCriteria kHeldOutTermination(cv::TermCriteria::COUNT +
                                               cv::TermCriteria::EPS,
                                           30, 1e-10);

bool Fit(DistortionModel model, const CvViews& views, cv::Size size,
         ModelFit* fit, std::string* error) {
  cv::Mat std_extrinsics, per_view;
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    fit->rms =
        cv::calibrateCamera(views.object, views.image, size, fit->k, fit->d,
                            rvecs, tvecs, fit->std_intrinsics, std_extrinsics,
                            per_view, CalibFlags(model), kCalibTermination);
  } catch (const cv::Exception& e) {
    *error = std::string("camera calibration failed: ") + e.what();
    return false;
  }
  fit->view_rms.assign(per_view.begin<double>(), per_view.end<double>());
  return std::isfinite(fit->rms);
}

// Mean squared reprojection error (px^2 per point) of each view under
// `model` fitted without that view's fold; the view's own pose is fitted to
// it alone (IPPE for the planar target, then Levenberg-Marquardt). The
// folds' fits start from `all` (the model fitted to every view), which
// saves most of their iterations.
bool HeldOutErrors(DistortionModel model, const ModelFit& all,
                   const CvViews& views, cv::Size size, int folds,
                   std::vector<double>* mse) {
  const int n = static_cast<int>(views.object.size());
  const int k_folds = std::min(folds, n);
  mse->assign(n, NAN);
  for (int f = 0; f < k_folds; ++f) {
    CvViews train;
    for (int i = 0; i < n; ++i) {
      if (i % k_folds == f) continue;
      train.object.push_back(views.object[i]);
      train.image.push_back(views.image[i]);
    }
    cv::Mat k = all.k.clone(), d = all.d.clone();
    std::vector<cv::Mat> rvecs, tvecs;
    try {
      const double rms = cv::calibrateCamera(
          train.object, train.image, size, k, d, rvecs, tvecs,
          CalibFlags(model) | cv::CALIB_USE_INTRINSIC_GUESS,
          kHeldOutTermination);
      if (!std::isfinite(rms)) return false;
      for (int i = f; i < n; i += k_folds) {
        cv::Mat rvec, tvec;
        if (!cv::solvePnP(views.object[i], views.image[i], k, d, rvec, tvec,
                          false, cv::SOLVEPNP_IPPE))
          return false;
        cv::solvePnPRefineLM(views.object[i], views.image[i], k, d, rvec, tvec);
        std::vector<cv::Point2f> projected;
        cv::projectPoints(views.object[i], rvec, tvec, k, d, projected);
        double sum = 0;
        for (size_t j = 0; j < projected.size(); ++j) {
          const cv::Point2f e = projected[j] - views.image[i][j];
          sum += double(e.x) * e.x + double(e.y) * e.y;
        }
        (*mse)[i] = sum / std::max<size_t>(1, projected.size());
      }
    } catch (const cv::Exception&) {
      return false;
    }
  }
  for (double v : *mse)
    if (!std::isfinite(v)) return false;
  return true;
}

tracking::Camera ToCamera(const ModelFit& fit, int width, int height) {
  tracking::Camera c;
  c.width = width;
  c.height = height;
  c.fx = fit.k.at<double>(0, 0);
  c.fy = fit.k.at<double>(1, 1);
  c.cx = fit.k.at<double>(0, 2);
  c.cy = fit.k.at<double>(1, 2);
  for (int i = 0; i < std::min<int>(8, fit.d.total()); ++i)
    c.dist[i] = fit.d.at<double>(i);
  return c;
}

}  // namespace

bool CalibrateCamera(const CameraCalibOptions& options,
                     const std::vector<CalibView>& all_views, int width,
                     int height, tracking::Camera* camera,
                     CameraCalibSummary* summary, std::string* error) {
  if (!options.IsValid(error)) return false;
  *summary = CameraCalibSummary();
  std::vector<CalibView> views;
  if (static_cast<int>(all_views.size()) > options.max_views) {
    for (int i = 0; i < options.max_views; ++i)
      views.push_back(all_views[i * all_views.size() / options.max_views]);
  } else {
    views = all_views;
  }
  const cv::Size size(width, height);
  auto too_few = [&] {
    if (static_cast<int>(views.size()) >= options.min_views) return false;
    *error = "too few views: " + std::to_string(views.size()) +
             " sharp, distinct views of the target (need " +
             std::to_string(options.min_views) +
             "); move the target around the whole image";
    return true;
  };
  if (too_few()) return false;

  // Outlier views, screened with the forced model or, when choosing, with
  // k3 free (a k3 = 0 fit of a strongly distorting lens would flag the
  // views that reach the image corners, the very ones that decide k3).
  const DistortionModel screen = options.distortion == DistortionModel::kAuto
                                     ? DistortionModel::kK1K2K3
                                     : options.distortion;
  ModelFit first;
  if (!Fit(screen, ToCv(views), size, &first, error)) return false;
  const double limit =
      std::max(options.outlier_floor_px,
               options.outlier_factor * Median(first.view_rms));
  std::vector<CalibView> inliers;
  for (size_t i = 0; i < views.size(); ++i)
    if (first.view_rms[i] <= limit) inliers.push_back(views[i]);
  const bool dropped = inliers.size() < views.size();
  if (dropped) {
    summary->views_dropped = static_cast<int>(views.size() - inliers.size());
    views = std::move(inliers);
    if (too_few()) return false;
  }
  const CvViews cv_views = ToCv(views);

  // Every candidate: fitted to all views, and cross-validated.
  std::vector<ModelFit> fits;
  summary->folds = std::min<int>(options.folds, views.size());
  for (DistortionModel m : kDistortionCandidates) {
    DistortionScore score;
    score.model = m;
    ModelFit fit;
    std::vector<double> mse;
    std::string fit_error;
    if (m == screen && !dropped) {
      fit = first;
    } else if (!Fit(m, cv_views, size, &fit, &fit_error)) {
      if (m == options.distortion) {
        *error = fit_error;
        return false;
      }
      fit = ModelFit();
    }
    if (!fit.k.empty() &&
        HeldOutErrors(m, fit, cv_views, size, options.folds, &mse)) {
      score.ok = true;
      score.rms_px = fit.rms;
      score.fx = fit.k.at<double>(0, 0);
      score.fy = fit.k.at<double>(1, 1);
      // Mean and standard error over views (each view's points together:
      // they share its fitted pose).
      double sum = 0, sq = 0;
      for (double e : mse) sum += e;
      const double mean = sum / mse.size();
      for (double e : mse) sq += (e - mean) * (e - mean);
      score.heldout_mse_px2 = mean;
      score.heldout_mse_se_px2 =
          std::sqrt(sq / std::max<size_t>(1, mse.size() - 1) / mse.size());
      score.heldout_rms_px = std::sqrt(mean);
    } else if (!fit.k.empty()) {
      score.rms_px = fit.rms;
      score.fx = fit.k.at<double>(0, 0);
      score.fy = fit.k.at<double>(1, 1);
    }
    summary->models.push_back(score);
    fits.push_back(fit);
  }

  // The choice: the simplest model whose held-out mean squared error is
  // within one standard error (over views) of the lowest.
  int chosen = -1;
  if (options.distortion == DistortionModel::kAuto) {
    summary->model_chosen = true;
    int best = -1;
    for (size_t m = 0; m < summary->models.size(); ++m)
      if (summary->models[m].ok &&
          (best < 0 || summary->models[m].heldout_mse_px2 <
                           summary->models[best].heldout_mse_px2))
        best = static_cast<int>(m);
    if (best < 0) {
      *error = "camera calibration failed: no distortion model could be fitted";
      return false;
    }
    summary->choice_limit_mse_px2 = summary->models[best].heldout_mse_px2 +
                                    summary->models[best].heldout_mse_se_px2;
    for (size_t m = 0; m < summary->models.size() && chosen < 0; ++m)
      if (summary->models[m].ok &&
          summary->models[m].heldout_mse_px2 <= summary->choice_limit_mse_px2)
        chosen = static_cast<int>(m);
  } else {
    for (size_t m = 0; m < summary->models.size(); ++m)
      if (summary->models[m].model == options.distortion)
        chosen = static_cast<int>(m);
  }
  const ModelFit& fit = fits[chosen];
  summary->model = summary->models[chosen].model;
  tracking::Camera c = ToCamera(fit, width, height);
  if (!c.IsValid(error)) return false;
  *camera = c;
  summary->views = static_cast<int>(views.size());
  summary->rms_px = fit.rms;
  summary->view_rms_px = fit.view_rms;
  for (const CalibView& v : views) summary->frames.push_back(v.frame);
  summary->std_fx = fit.std_intrinsics.at<double>(0);
  summary->std_fy = fit.std_intrinsics.at<double>(1);
  summary->std_cx = fit.std_intrinsics.at<double>(2);
  summary->std_cy = fit.std_intrinsics.at<double>(3);
  ViewCoverage(views, width, height, &summary->grid_coverage,
               &summary->hull_coverage);
  return true;
}

}  // namespace ripple::calib
