#include "tracking/clean_plate.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

namespace ripple::tracking {
namespace {

// Board plane z = 0 (tank frame) -> ideal-pinhole pixel: K [r1 r2 t].
cv::Matx33d ImageFromBoard(const Camera& camera, const Pose& cam_from_tank) {
  const Eigen::Matrix3d r = cam_from_tank.R();
  const Eigen::Vector3d& t = cam_from_tank.translation;
  const cv::Matx33d k(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0,
                      1);
  const cv::Matx33d rt(r(0, 0), r(0, 1), t.x(), r(1, 0), r(1, 1), t.y(),
                       r(2, 0), r(2, 1), t.z());
  return k * rt;
}

inline cv::Vec3f Bgr(const cv::Vec4b& v) {
  return {float(v[0]), float(v[1]), float(v[2])};
}

inline float MaxAbs3(const cv::Vec3f& a, const cv::Vec3f& b) {
  return std::max(
      {std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
}

}  // namespace

bool CleanPlateOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = std::string("clean plate: ") + m;
    return false;
  };
  if (!(texel_m > 1e-4 && texel_m < 0.02))
    return fail("texel must be 0.1-20 mm");
  if (!(margin_m >= 0 && margin_m < 1)) return fail("margin must be 0-1 m");
  if (!(surround_m >= 0 && surround_m <= margin_m))
    return fail("surround must be 0 to the margin");
  if (!(low_threshold > 0 && high_threshold >= low_threshold &&
        high_threshold < 256))
    return fail("thresholds must satisfy 0 < low <= high < 256");
  if (!(shadow_min_ratio > 0 && shadow_min_ratio <= 1))
    return fail("shadow ratio must be in (0, 1]");
  if (!(shadow_chroma_tolerance >= 0 && shadow_chroma_tolerance < 1))
    return fail("shadow chroma tolerance must be in [0, 1)");
  if (evidence_cap_frames < 1 || evidence_cap_frames > 60000)
    return fail("evidence cap must be 1-60000 frames");
  if (takeover_frames < 1 || takeover_frames > 60000)
    return fail("takeover must be 1-60000 frames");
  if (!(learn_rate > 0 && learn_rate <= 1))
    return fail("learn rate must be in (0, 1]");
  if (min_region_texels < 0) return fail("minimum region must be >= 0");
  if (grow_px < 0 || grow_px > 16) return fail("mask growth must be 0-16 px");
  return true;
}

CleanPlate::CleanPlate(const Camera& camera, double tank_size_x_m,
                       double tank_size_y_m, double box_top_m,
                       const CleanPlateOptions& options)
    : camera_(camera),
      options_(options),
      size_x_m_(tank_size_x_m),
      size_y_m_(tank_size_y_m),
      box_top_m_(box_top_m) {
  const double sx = tank_size_x_m + 2 * options.margin_m;
  const double sy = tank_size_y_m + 2 * options.margin_m;
  plate_w_ = std::max(1, static_cast<int>(std::ceil(sx / options.texel_m)));
  plate_h_ = std::max(1, static_cast<int>(std::ceil(sy / options.texel_m)));
  origin_m_ = {-0.5 * plate_w_ * options.texel_m,
               -0.5 * plate_h_ * options.texel_m};
  foreground_ = cv::Mat::zeros(camera.height, camera.width, CV_8U);
  if (camera.HasDistortion()) {
    undistort_x_.create(camera.height, camera.width, CV_32F);
    undistort_y_.create(camera.height, camera.width, CV_32F);
    for (int v = 0; v < camera.height; ++v) {
      float* mx = undistort_x_.ptr<float>(v);
      float* my = undistort_y_.ptr<float>(v);
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector2d d = camera.DistortNormalized(
            (u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy);
        mx[u] = static_cast<float>(d.x());
        my[u] = static_cast<float>(d.y());
      }
    }
  }
  Reset();
}

void CleanPlate::Reset() {
  background_ = cv::Mat::zeros(plate_h_, plate_w_, CV_32FC3);
  challenger_ = cv::Mat::zeros(plate_h_, plate_w_, CV_32FC3);
  background_n_ = cv::Mat::zeros(plate_h_, plate_w_, CV_16U);
  challenger_n_ = cv::Mat::zeros(plate_h_, plate_w_, CV_16U);
  known_texels_ = 0;
  plate_bgra_ = cv::Mat::zeros(plate_h_, plate_w_, CV_8UC4);
  foreground_.setTo(0);
  plate_foreground_ = cv::Mat::zeros(plate_h_, plate_w_, CV_8U);
  last_roi_ = cv::Rect();
  window_ = cv::Rect();
  gain_ = 1.0;
  ++plate_counter_;
  summary_ = CleanPlateSummary();
  ComposeShownPlate();
}

bool CleanPlate::SetBoardPrior(const cv::Mat& design_levels,
                               const cv::Mat& valid) {
  if (design_levels.type() != CV_32FC3 || valid.type() != CV_8U ||
      design_levels.size() != plate_size() || valid.size() != plate_size())
    return false;
  prior_.create(plate_h_, plate_w_, CV_8UC4);
  for (int j = 0; j < plate_h_; ++j) {
    const cv::Vec3f* d = design_levels.ptr<cv::Vec3f>(j);
    const std::uint8_t* v = valid.ptr(j);
    cv::Vec4b* out = prior_.ptr<cv::Vec4b>(j);
    for (int i = 0; i < plate_w_; ++i)
      out[i] =
          cv::Vec4b(cv::saturate_cast<std::uint8_t>(d[i][0]),
                    cv::saturate_cast<std::uint8_t>(d[i][1]),
                    cv::saturate_cast<std::uint8_t>(d[i][2]), v[i] ? 255 : 0);
  }
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::erode(prior_, prior_lo_, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  cv::dilate(prior_, prior_hi_, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  // Validity over the whole neighbourhood: the eroded alpha, on both.
  for (int j = 0; j < plate_h_; ++j) {
    cv::Vec4b* lo = prior_lo_.ptr<cv::Vec4b>(j);
    cv::Vec4b* hi = prior_hi_.ptr<cv::Vec4b>(j);
    for (int i = 0; i < plate_w_; ++i) hi[i][3] = lo[i][3];
  }
  ComposeShownPlate();
  return true;
}

void CleanPlate::Undistort(const cv::Mat& bgr, const cv::Rect& window,
                           cv::Mat* out) {
  if (undistort_x_.empty()) {
    *out = bgr(window);
    return;
  }
  cv::remap(bgr, *out, undistort_x_(window), undistort_y_(window),
            cv::INTER_LINEAR, cv::BORDER_REPLICATE);
}

const CleanPlateSummary& CleanPlate::Process(const cv::Mat& bgr,
                                             const Pose& cam_from_tank,
                                             const cv::Mat& exclude,
                                             const cv::Mat& object) {
  summary_ = CleanPlateSummary();
  cv::Rect window =
      TankWindow(camera_, cam_from_tank, size_x_m_, size_y_m_, box_top_m_, 4);
  const double surround = std::min(options_.surround_m, options_.margin_m);
  if (surround > 0) {
    window |= TankWindow(camera_, cam_from_tank, size_x_m_ + 2 * surround,
                         size_y_m_ + 2 * surround, 0.0, 4);
  }
  // The last window's mask is cleared; the new one is written below.
  if (window_.area() > 0) foreground_(window_).setTo(0);
  window &= cv::Rect(0, 0, camera_.width, camera_.height);
  window_ = cv::Rect();
  auto give_up = [&]() -> const CleanPlateSummary& {
    plate_foreground_.setTo(0);
    last_roi_ = cv::Rect();
    return summary_;
  };
  if (bgr.type() != CV_8UC3 || bgr.cols != camera_.width ||
      bgr.rows != camera_.height || window.area() <= 0)
    return give_up();
  const cv::Matx33d image_from_board = ImageFromBoard(camera_, cam_from_tank);
  const double s = options_.texel_m;
  const cv::Matx33d board_from_plate(s, 0, origin_m_.x + 0.5 * s, 0, s,
                                     origin_m_.y + 0.5 * s, 0, 0, 1);
  const cv::Matx33d image_from_plate = image_from_board * board_from_plate;
  // The plate's corners must lie in front of the camera, or the homography
  // folds the board behind it into the image.
  for (int c = 0; c < 4; ++c) {
    const cv::Vec3d corner((c & 1) ? plate_w_ : 0, (c & 2) ? plate_h_ : 0, 1);
    if ((image_from_plate * corner)[2] <= 1e-6) return give_up();
  }
  // The plate texels the window sees (its corners on the board, grown by
  // three texels for the neighbourhoods and the interpolation).
  const cv::Matx33d plate_from_image = image_from_plate.inv();
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (int c = 0; c < 4; ++c) {
    const cv::Vec3d q = plate_from_image *
                        cv::Vec3d(window.x + ((c & 1) ? window.width : 0),
                                  window.y + ((c & 2) ? window.height : 0), 1);
    if (q[2] <= 1e-12) {  // a window corner above the horizon
      x0 = y0 = -1e18;
      x1 = y1 = 1e18;
      break;
    }
    x0 = std::min(x0, q[0] / q[2]);
    x1 = std::max(x1, q[0] / q[2]);
    y0 = std::min(y0, q[1] / q[2]);
    y1 = std::max(y1, q[1] / q[2]);
  }
  // ... and the board the tank's box hides: its corners seen from the
  // camera, down to the board plane.
  const Eigen::Vector3d eye = cam_from_tank.Inverse().translation;
  double bx0 = 1e18, by0 = 1e18, bx1 = -1e18, by1 = -1e18;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p((c & 1 ? 0.5 : -0.5) * size_x_m_,
                            (c & 2 ? 0.5 : -0.5) * size_y_m_,
                            c & 4 ? box_top_m_ : 0.0);
    if (eye.z() <= p.z() + 1e-3) {  // the camera below the box's top
      bx0 = by0 = -1e18;
      bx1 = by1 = 1e18;
      break;
    }
    const Eigen::Vector3d q = eye + (p - eye) * (eye.z() / (eye.z() - p.z()));
    bx0 = std::min(bx0, q.x());
    bx1 = std::max(bx1, q.x());
    by0 = std::min(by0, q.y());
    by1 = std::max(by1, q.y());
  }
  // ... and the board around it that the renderer changes.
  bx0 = std::min(bx0, -0.5 * size_x_m_ - surround);
  bx1 = std::max(bx1, 0.5 * size_x_m_ + surround);
  by0 = std::min(by0, -0.5 * size_y_m_ - surround);
  by1 = std::max(by1, 0.5 * size_y_m_ + surround);
  x0 = std::max(x0, (bx0 - origin_m_.x) / s - 0.5);
  x1 = std::min(x1, (bx1 - origin_m_.x) / s - 0.5);
  y0 = std::max(y0, (by0 - origin_m_.y) / s - 0.5);
  y1 = std::min(y1, (by1 - origin_m_.y) / s - 0.5);
  const cv::Rect plate_rect(0, 0, plate_w_, plate_h_);
  auto to_int = [](double v) {
    return static_cast<int>(std::clamp(v, -1e6, 1e6));
  };
  const cv::Rect roi =
      cv::Rect(
          cv::Point(to_int(std::floor(x0)) - 3, to_int(std::floor(y0)) - 3),
          cv::Point(to_int(std::ceil(x1)) + 4, to_int(std::ceil(y1)) + 4)) &
      plate_rect;
  if (roi.area() <= 0) return give_up();
  window_ = window;
  summary_.visited_texels = roi.area();
  const cv::Matx33d window_from_roi =
      cv::Matx33d(1, 0, -window.x, 0, 1, -window.y, 0, 0, 1) *
      image_from_plate * cv::Matx33d(1, 0, roi.x, 0, 1, roi.y, 0, 0, 1);

  cv::Mat frame;
  Undistort(bgr, window, &frame);
  // The frame on the plate, with alpha: 255 seen, 0 outside the window
  // or on a known object (cleared only inside the object's bounding box).
  cv::Mat exclude_in_window;
  if (!exclude.empty()) exclude_in_window = exclude(window);
  cv::cvtColor(frame, frame_bgra_, cv::COLOR_BGR2BGRA);
  const cv::Rect exclude_box = exclude_in_window.empty()
                                   ? cv::Rect()
                                   : cv::boundingRect(exclude_in_window);
  if (exclude_box.area() > 0) {
    const cv::Rect& box = exclude_box;
    for (int y = box.y; y < box.y + box.height; ++y) {
      const std::uint8_t* ex = exclude_in_window.ptr(y);
      cv::Vec4b* f = frame_bgra_.ptr<cv::Vec4b>(y);
      for (int x = box.x; x < box.x + box.width; ++x)
        if (ex[x]) f[x][3] = 0;
    }
  }
  cv::Mat& seen = seen_;
  cv::warpPerspective(frame_bgra_, seen, window_from_roi, roi.size(),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                      cv::BORDER_CONSTANT, cv::Scalar::all(0));
  // Within 2 texels of a known object (its blurred edge) or outside the
  // view, texels are judged but not learned: alpha 128.
  const cv::Mat k5 = cv::getStructuringElement(cv::MORPH_RECT, {5, 5});
  {
    cv::Mat& full = full_;
    cv::extractChannel(seen, full, 3);
    cv::threshold(full, full, 254, 255, cv::THRESH_BINARY);
    cv::erode(full, grown_, k5, {-1, -1}, 1, cv::BORDER_REPLICATE);
    for (int j = 0; j < roi.height; ++j) {
      cv::Vec4b* o = seen.ptr<cv::Vec4b>(j);
      const std::uint8_t* g = grown_.ptr(j);
      for (int i = 0; i < roi.width; ++i)
        if (!g[i] && o[i][3] >= 100) o[i][3] = 128;
    }
  }
  EstimateGains(bgr, cam_from_tank, exclude);

  cv::Mat& mask = mask_;
  Classify(seen, roi, &mask);
  // Into the window (only around the mask's texels): bilinear, then half
  // coverage; never over known objects.
  const cv::Rect found = cv::boundingRect(mask);
  if (found.area() > 0) {
    double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
    for (int c = 0; c < 4; ++c) {
      const cv::Vec3d q =
          window_from_roi *
          cv::Vec3d(found.x - 1 + ((c & 1) ? found.width + 2 : 0),
                    found.y - 1 + ((c & 2) ? found.height + 2 : 0), 1);
      u0 = std::min(u0, q[0] / q[2]);
      u1 = std::max(u1, q[0] / q[2]);
      v0 = std::min(v0, q[1] / q[2]);
      v1 = std::max(v1, q[1] / q[2]);
    }
    const int pad = 2 + options_.grow_px;
    const cv::Rect sub = cv::Rect(cv::Point(to_int(std::floor(u0)) - pad,
                                            to_int(std::floor(v0)) - pad),
                                  cv::Point(to_int(std::ceil(u1)) + pad + 1,
                                            to_int(std::ceil(v1)) + pad + 1)) &
                         cv::Rect(0, 0, window.width, window.height);
    if (sub.area() > 0) {
      const cv::Matx33d sub_from_roi =
          cv::Matx33d(1, 0, -sub.x, 0, 1, -sub.y, 0, 0, 1) * window_from_roi;
      cv::warpPerspective(mask, in_window_, sub_from_roi, sub.size(),
                          cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                          cv::Scalar::all(0));
      cv::Mat out = foreground_(window)(sub);
      cv::threshold(in_window_, out, 127, 255, cv::THRESH_BINARY);
      if (options_.grow_px > 0) {
        const int k = 2 * options_.grow_px + 1;
        cv::dilate(out, out, cv::getStructuringElement(cv::MORPH_RECT, {k, k}));
      }
      if (!exclude_in_window.empty())
        out.setTo(0, exclude_in_window(sub));
      else  // with known objects, counted below over the whole window
        summary_.foreground_px = cv::countNonZero(out);
    }
  }

  // Around the known objects only (their bounding box, grown by the
  // neighbourhoods below).
  const cv::Rect window_rect(0, 0, window.width, window.height);
  if (!object.empty() && object.size() == foreground_.size()) {
    const cv::Rect box = cv::boundingRect(object(window));
    const cv::Rect sub =
        cv::Rect(box.x - 4, box.y - 4, box.width + 8, box.height + 8) &
        window_rect;
    if (box.area() > 0 && sub.area() > 0) {
      cv::Mat out = foreground_(window)(sub);
      ClassifyObject(frame(sub), object(window)(sub), &out);
    }
  }
  // The plate's texels are coarser than the pixels, so the mask stops a
  // pixel or two short of a known object it touches: the gap between the
  // two is closed (a closing of mask and object together, the object
  // itself left out).
  if (exclude_box.area() > 0) {
    const cv::Rect& box = exclude_box;
    const cv::Rect sub =
        cv::Rect(box.x - 4, box.y - 4, box.width + 8, box.height + 8) &
        window_rect;
    if (box.area() > 0 && sub.area() > 0) {
      cv::Mat out = foreground_(window)(sub);
      const cv::Mat ex = exclude_in_window(sub);
      cv::Mat& both = both_;
      cv::bitwise_or(out, ex, both);
      cv::morphologyEx(both, both, cv::MORPH_CLOSE,
                       cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
      both.setTo(0, ex);
      out |= both;
    }
  }
  if (!exclude_in_window.empty())
    summary_.foreground_px = cv::countNonZero(foreground_(window));

  // Texels at the mask and 2 around it (an occluder's blurred edge mixes
  // it with the board) only feed the challengers.
  cv::Mat& near_fg = near_fg_;
  cv::dilate(mask, near_fg, k5);
  for (int j = 0; j < roi.height; ++j) {
    cv::Vec4b* o = seen.ptr<cv::Vec4b>(j);
    const std::uint8_t* m = near_fg.ptr(j);
    for (int i = 0; i < roi.width; ++i)
      if (m[i] && o[i][3] >= 250) o[i][3] = 128;
  }
  Learn(seen, roi);
  if (last_roi_.area() > 0) plate_foreground_(last_roi_).setTo(0);
  mask.copyTo(plate_foreground_(roi));
  last_roi_ = roi;
  summary_.gain = gain_;
  ComposeShownPlate();
  return summary_;
}

void CleanPlate::ComposeShownPlate() {
  if (prior_.empty()) {
    // The plate itself (sharing its pixels, which Learn updates in place).
    if (shown_.data != plate_bgra_.data || shown_from_plate_ != plate_counter_)
      ++shown_counter_;
    shown_ = plate_bgra_;
    shown_from_plate_ = plate_counter_;
    return;
  }
  // Design levels to plate units: the frame shows design x prior_gain and
  // plate x gain.
  const cv::Vec3f scale = prior_gain_ * static_cast<float>(1.0 / gain_);
  bool moved = shown_.data == plate_bgra_.data || shown_.empty() ||
               shown_from_plate_ != plate_counter_;
  for (int c = 0; c < 3; ++c)
    moved |= std::abs(scale[c] - shown_scale_[c]) >
             kShownDesignGainStep * shown_scale_[c];
  if (!moved) return;
  if (shown_.data == plate_bgra_.data) shown_.release();  // not the plate's
  shown_.create(plate_h_, plate_w_, CV_8UC4);
  for (int j = 0; j < plate_h_; ++j) {
    const cv::Vec4b* p = plate_bgra_.ptr<cv::Vec4b>(j);
    const cv::Vec4b* q = prior_.ptr<cv::Vec4b>(j);
    cv::Vec4b* out = shown_.ptr<cv::Vec4b>(j);
    for (int i = 0; i < plate_w_; ++i) {
      if (p[i][3] == 255 || q[i][3] != 255) {
        out[i] = p[i];
        continue;
      }
      for (int c = 0; c < 3; ++c)
        out[i][c] = cv::saturate_cast<std::uint8_t>(q[i][c] * scale[c]);
      out[i][3] = 255;
    }
  }
  shown_scale_ = scale;
  shown_from_plate_ = plate_counter_;
  ++shown_counter_;
}

namespace {

// The ratio the board's samples agree on: the peak of the histogram of
// their logarithms (1% bins, smoothed over +-2 bins), refined by the median
// of the samples within 5% of it; clamped to [0.25, 4]. Exposure moves by a
// few percent a frame, so the peak is sought within 10% of the last frame's
// ratio `previous` while at least a quarter of the samples lie there, and
// over all ratios otherwise. A hand that enters over the board is not in
// the last frame's mask, so its samples are taken too: over plain paper
// they agree on a ratio of their own (skin over paper, about 0.6), which
// the median, and the histogram's highest peak, take once the hand covers
// enough of the board; the whole board then read as brighter than the
// plate and joined the hand.
float PeakRatio(const std::vector<float>& v, float previous) {
  constexpr float kLo = -1.3863f, kStep = 0.01f;  // ln 0.25, 1% bins
  constexpr int kBins = 278;                      // to ln 4
  auto bin = [&](float r) {
    const float l = std::log(std::max(r, 1e-6f));
    return std::clamp(static_cast<int>(std::floor((l - kLo) / kStep)), 0,
                      kBins - 1);
  };
  int hist[kBins] = {};
  for (float r : v) ++hist[bin(r)];
  auto peak_in = [&](int b0, int b1, int* best_count) {
    int best = b0;
    *best_count = -1;
    for (int b = b0; b <= b1; ++b) {
      int count = 0;
      for (int d = -2; d <= 2; ++d)
        if (b + d >= 0 && b + d < kBins) count += hist[b + d];
      if (count > *best_count) {
        *best_count = count;
        best = b;
      }
    }
    return best;
  };
  // Within 10% of the last ratio (ln 1.1 = 9.5 bins) while a quarter of
  // the samples lie there.
  const int last = bin(previous);
  const int b0 = std::max(0, last - 10), b1 = std::min(kBins - 1, last + 10);
  int near_count = 0;
  for (int b = b0; b <= b1; ++b) near_count += hist[b];
  int best_count = 0;
  const int best = 4 * near_count >= static_cast<int>(v.size())
                       ? peak_in(b0, b1, &best_count)
                       : peak_in(0, kBins - 1, &best_count);
  const float peak = std::exp(kLo + (best + 0.5f) * kStep);
  std::vector<float> near;
  near.reserve(v.size());
  for (float r : v)
    if (std::abs(r / peak - 1.0f) <= 0.05f) near.push_back(r);
  float out = peak;
  if (!near.empty()) {
    auto mid = near.begin() + near.size() / 2;
    std::nth_element(near.begin(), mid, near.end());
    out = *mid;
  }
  return std::clamp(out, 0.25f, 4.0f);
}

}  // namespace

void CleanPlate::EstimateGains(const cv::Mat& bgr, const Pose& cam_from_tank,
                               const cv::Mat& exclude) {
  // The plate's gain: the ratio of frame to plate brightness that known,
  // bright enough board texels agree on (PeakRatio; tag black carries no
  // exposure information); the design's: per channel over its paper. Sampled
  // over the whole plate (every seventh texel each way), where the camera sees
  // it, away from known objects and the last frame's occluders, so an occluder
  // over the tank does not move the medians.
  std::vector<float> ratios, prior_ratios[3];
  std::vector<std::pair<cv::Vec3b, cv::Vec3f>> design_samples;
  const double s = options_.texel_m;
  // Board points (x, y, 0) to the camera: the rotation's first two columns.
  const Eigen::Matrix3d r = cam_from_tank.R();
  const Eigen::Vector3d r_x = r.col(0), r_y = r.col(1);
  const bool distorted = camera_.HasDistortion();
  for (int j = 3; j < plate_h_; j += 7) {
    const cv::Vec4b* p = plate_bgra_.ptr<cv::Vec4b>(j);
    const cv::Vec4b* q = prior_.empty() ? nullptr : prior_.ptr<cv::Vec4b>(j);
    const std::uint8_t* last = plate_foreground_.ptr(j);
    for (int i = 3; i < plate_w_; i += 7) {
      if (last[i]) continue;
      const bool plate_ok = p[i][3] == 255 && p[i][0] + p[i][1] + p[i][2] >= 90;
      const bool prior_ok = q && q[i][3] == 255 && q[i][0] > 150 &&
                            q[i][1] > 150 && q[i][2] > 150;
      if (!plate_ok && !prior_ok) continue;
      const Eigen::Vector3d c = r_x * (origin_m_.x + s * (i + 0.5)) +
                                r_y * (origin_m_.y + s * (j + 0.5)) +
                                cam_from_tank.translation;
      if (c.z() < 1e-3) continue;
      const Eigen::Vector2d ideal(camera_.fx * c.x() / c.z() + camera_.cx,
                                  camera_.fy * c.y() / c.z() + camera_.cy);
      const Eigen::Vector2d raw = distorted ? camera_.Project(c) : ideal;
      const int u = static_cast<int>(std::lround(raw.x()));
      const int v = static_cast<int>(std::lround(raw.y()));
      const int ui = static_cast<int>(std::lround(ideal.x()));
      const int vi = static_cast<int>(std::lround(ideal.y()));
      if (u < 0 || v < 0 || u >= bgr.cols || v >= bgr.rows) continue;
      if (!exclude.empty() && ui >= 0 && vi >= 0 && ui < exclude.cols &&
          vi < exclude.rows && exclude.at<std::uint8_t>(vi, ui))
        continue;
      const cv::Vec3b o = bgr.at<cv::Vec3b>(v, u);
      if (plate_ok)
        ratios.push_back(static_cast<float>(o[0] + o[1] + o[2]) /
                         static_cast<float>(p[i][0] + p[i][1] + p[i][2]));
      if (prior_ok) {
        for (int k = 0; k < 3; ++k)
          prior_ratios[k].push_back(static_cast<float>(o[k]) / q[i][k]);
        design_samples.push_back({o, Bgr(q[i])});
      }
    }
  }
  if (ratios.size() >= 100)
    gain_ = PeakRatio(ratios, static_cast<float>(gain_));
  if (prior_ratios[0].size() >= 100)
    for (int k = 0; k < 3; ++k)
      prior_gain_[k] = PeakRatio(prior_ratios[k], prior_gain_[k]);
  // A design the camera does not see (another board, another floor): when
  // most of the paper samples are not what it allows, frame after frame, it
  // is dropped and the plate learns without it.
  if (design_samples.size() >= 100) {
    int agree = 0;
    for (const auto& [o, q] : design_samples)
      agree += PriorAllows(cv::Vec3f(o[0], o[1], o[2]), q);
    summary_.design_agreement = double(agree) / design_samples.size();
    design_strikes_ = summary_.design_agreement < 0.6 ? design_strikes_ + 1 : 0;
    if (design_strikes_ >= 5) {
      prior_.release();
      prior_lo_.release();
      prior_hi_.release();
      design_dropped_ = true;
    }
  }
}

bool CleanPlate::PriorAllows(const cv::Vec3f& o, const cv::Vec3f& p) const {
  // The light may change the brightness, not the colour: the brightness
  // ratio within the illumination range, and the chromaticity kept. Shadows
  // are not allowed: a texel learns its colour in the light, and grey
  // mixtures of a dark object's edge with paper read as shadow.
  const cv::Vec3f q = p.mul(prior_gain_);
  const float lo = static_cast<float>(options_.illumination_low);
  const float hi = static_cast<float>(options_.illumination_high);
  const float t_low = static_cast<float>(options_.low_threshold);
  for (int c = 0; c < 3; ++c)
    if (o[c] < lo * q[c] - t_low || o[c] > hi * q[c] + t_low) return false;
  const float qq = q.dot(q);
  if (!(qq > 0)) return true;
  const float a = o.dot(q) / qq;
  const cv::Vec3f r = o - a * q;
  const float res = std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
  return res <= static_cast<float>(options_.shadow_chroma_tolerance) * a *
                        std::max({q[0], q[1], q[2]}) +
                    0.25f * t_low;
}

void CleanPlate::Classify(const cv::Mat& seen, const cv::Rect& roi,
                          cv::Mat* mask) {
  const int w = roi.width, h = roi.height;
  // The learned plate's 3x3 range (one texel more each way for the
  // neighbourhoods).
  const cv::Rect grown = cv::Rect(roi.x - 1, roi.y - 1, w + 2, h + 2) &
                         cv::Rect(0, 0, plate_w_, plate_h_);
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::Mat& plo = plo_;
  cv::Mat& phi = phi_;
  cv::erode(plate_bgra_(grown), plo, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  cv::dilate(plate_bgra_(grown), phi, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  const int dx = roi.x - grown.x, dy = roi.y - grown.y;
  const float g = static_cast<float>(gain_);
  const float ill_lo = static_cast<float>(options_.illumination_low);
  const float ill_hi = static_cast<float>(options_.illumination_high);
  const float t_low = static_cast<float>(options_.low_threshold);
  const float t_high = static_cast<float>(options_.high_threshold);
  const float min_ratio = static_cast<float>(options_.shadow_min_ratio);
  const float chroma_tol = static_cast<float>(options_.shadow_chroma_tolerance);
  const bool have_prior = !prior_.empty();
  cv::Mat& weak = weak_;
  cv::Mat& strong = strong_;
  weak.create(h, w, CV_8U);
  strong.create(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    const int row = roi.y + j;
    const cv::Vec4b* o = seen.ptr<cv::Vec4b>(j);
    const cv::Vec4b* p = plate_bgra_.ptr<cv::Vec4b>(row) + roi.x;
    const cv::Vec4b* pl = plo.ptr<cv::Vec4b>(j + dy) + dx;
    const cv::Vec4b* ph = phi.ptr<cv::Vec4b>(j + dy) + dx;
    const cv::Vec4b* q =
        have_prior ? prior_.ptr<cv::Vec4b>(row) + roi.x : nullptr;
    const cv::Vec4b* ql =
        have_prior ? prior_lo_.ptr<cv::Vec4b>(row) + roi.x : nullptr;
    const cv::Vec4b* qh =
        have_prior ? prior_hi_.ptr<cv::Vec4b>(row) + roi.x : nullptr;
    const std::uint8_t* last = plate_foreground_.ptr(row) + roi.x;
    std::uint8_t* wk = weak.ptr(j);
    std::uint8_t* st = strong.ptr(j);
    std::memset(wk, 0, static_cast<size_t>(w));
    std::memset(st, 0, static_cast<size_t>(w));
    for (int i = 0; i < w; ++i) {
      // Seen this frame, not on a known object.
      if (o[i][3] < 100) continue;
      float lo[3], hi[3], ratio = min_ratio;
      const bool learned = pl[i][3] == 255;
      if (learned) {
        // The learned plate, known over the whole neighbourhood.
        for (int c = 0; c < 3; ++c) {
          lo[c] = g * pl[i][c];
          hi[c] = g * ph[i][c];
        }
      } else if (q && ql[i][3] == 255) {
        // Not learned yet: the printed design under this frame's light;
        // shadows are judged against it under the dimmest light allowed.
        for (int c = 0; c < 3; ++c) {
          const float pg = prior_gain_[c];
          lo[c] = ill_lo * pg * ql[i][c];
          hi[c] = ill_hi * pg * qh[i][c];
        }
        ratio *= ill_lo;
      } else {
        continue;
      }
      const float f[3] = {float(o[i][0]), float(o[i][1]), float(o[i][2])};
      // Within the threshold of both ends: on the segment's near side.
      if (std::abs(f[0] - lo[0]) <= t_low && std::abs(f[1] - lo[1]) <= t_low &&
          std::abs(f[2] - lo[2]) <= t_low && std::abs(f[0] - hi[0]) <= t_low &&
          std::abs(f[1] - hi[1]) <= t_low && std::abs(f[2] - hi[2]) <= t_low)
        continue;
      // Distance from the segment lo-hi (the largest channel).
      const float d0 = hi[0] - lo[0], d1 = hi[1] - lo[1], d2 = hi[2] - lo[2];
      const float dd = d0 * d0 + d1 * d1 + d2 * d2;
      float t = 0;
      if (dd > 0)
        t = std::clamp(
            ((f[0] - lo[0]) * d0 + (f[1] - lo[1]) * d1 + (f[2] - lo[2]) * d2) /
                dd,
            0.0f, 1.0f);
      const float r0 = std::abs(f[0] - lo[0] - t * d0);
      const float r1 = std::abs(f[1] - lo[1] - t * d1);
      const float r2 = std::abs(f[2] - lo[2] - t * d2);
      const float d = std::max(r0, std::max(r1, r2));
      if (d <= t_low) continue;
      // A shadow: darker by a common factor, chromaticity kept.
      float mid[3];
      for (int c = 0; c < 3; ++c)
        mid[c] = learned ? g * p[i][c] : prior_gain_[c] * q[i][c];
      const float qq = mid[0] * mid[0] + mid[1] * mid[1] + mid[2] * mid[2];
      if (qq > 0) {
        const float a = (f[0] * mid[0] + f[1] * mid[1] + f[2] * mid[2]) / qq;
        if (a >= ratio && a < 1.0f) {
          const float s0 = std::abs(f[0] - a * mid[0]);
          const float s1 = std::abs(f[1] - a * mid[1]);
          const float s2 = std::abs(f[2] - a * mid[2]);
          const float top = std::max(mid[0], std::max(mid[1], mid[2]));
          if (std::max(s0, std::max(s1, s2)) <=
              chroma_tol * a * top + 0.5f * t_low)
            continue;
        }
      }
      wk[i] = 255;
      if (d > t_high || last[i]) st[i] = 255;
    }
  }
  // Spatial hysteresis: weak regions holding a strong texel, big enough.
  cv::Mat& labels = labels_;
  cv::Mat& stats = stats_;
  const int n =
      cv::connectedComponentsWithStats(weak, labels, stats, centroids_, 8);
  std::vector<std::uint8_t> keep(static_cast<size_t>(n), 0);
  for (int j = 0; j < h; ++j) {
    const int* l = labels.ptr<int>(j);
    const std::uint8_t* st = strong.ptr(j);
    for (int i = 0; i < w; ++i)
      if (st[i]) keep[static_cast<size_t>(l[i])] = 1;
  }
  keep[0] = 0;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) < options_.min_region_texels)
      keep[static_cast<size_t>(i)] = 0;
  mask->create(h, w, CV_8U);
  for (int j = 0; j < h; ++j) {
    const int* l = labels.ptr<int>(j);
    std::uint8_t* m = mask->ptr(j);
    for (int i = 0; i < w; ++i) m[i] = keep[static_cast<size_t>(l[i])] * 255;
  }
  cv::morphologyEx(*mask, *mask, cv::MORPH_CLOSE, k3, {-1, -1}, 1,
                   cv::BORDER_CONSTANT, cv::Scalar::all(0));
}

void CleanPlate::Learn(const cv::Mat& seen, const cv::Rect& roi) {
  const float inv_g = static_cast<float>(1.0 / gain_);
  const float tol = static_cast<float>(options_.low_threshold) * inv_g;
  const float rate = static_cast<float>(options_.learn_rate);
  const int cap = options_.evidence_cap_frames;
  const int takeover = options_.takeover_frames;
  int learned = 0;
  bool changed = false;
  for (int j = 0; j < roi.height; ++j) {
    const cv::Vec4b* o8 = seen.ptr<cv::Vec4b>(j);
    const int row = roi.y + j;
    cv::Vec3f* a = background_.ptr<cv::Vec3f>(row) + roi.x;
    cv::Vec3f* b = challenger_.ptr<cv::Vec3f>(row) + roi.x;
    std::uint16_t* na = background_n_.ptr<std::uint16_t>(row) + roi.x;
    std::uint16_t* nb = challenger_n_.ptr<std::uint16_t>(row) + roi.x;
    cv::Vec4b* out = plate_bgra_.ptr<cv::Vec4b>(row) + roi.x;
    const cv::Vec4b* design =
        prior_.empty() ? nullptr : prior_.ptr<cv::Vec4b>(row) + roi.x;
    for (int i = 0; i < roi.width; ++i) {
      if (o8[i][3] < 100) continue;
      const cv::Vec3f o(o8[i][0] * inv_g, o8[i][1] * inv_g, o8[i][2] * inv_g);
      // Colours the printed design rules out are never board (asked only
      // where a colour would become background); pixels at an occluder only
      // feed the challenger.
      auto design_ok = [&]() {
        return !design || design[i][3] != 255 ||
               PriorAllows(Bgr(o8[i]), Bgr(design[i]));
      };
      const bool learnable = o8[i][3] >= 250;
      // The plate shows the background colour: republished when it moves
      // (texels without one stay transparent).
      bool a_changed = false;
      if (na[i] == 0) {
        if (learnable && design_ok()) {
          a[i] = o;
          na[i] = 1;
          ++learned;
          ++known_texels_;
          a_changed = true;
        }
      } else if (MaxAbs3(o, a[i]) <= tol) {
        if (learnable) {
          a_changed = true;
          ++learned;
          a[i] += rate * (o - a[i]);
          na[i] = static_cast<std::uint16_t>(std::min<int>(cap, na[i] + 1));
          if (nb[i] > 0) --nb[i];
        }
      } else if (nb[i] > 0 && MaxAbs3(o, b[i]) <= tol) {
        b[i] += (o - b[i]) * (1.0f / (nb[i] + 1));
        nb[i] = static_cast<std::uint16_t>(
            std::min<int>(std::max(cap, takeover) + 1, nb[i] + 1));
        if (nb[i] > na[i] && nb[i] >= takeover && design_ok()) {
          std::swap(a[i], b[i]);
          a_changed = true;
          na[i] = nb[i];
          nb[i] = 0;
        }
      } else {
        b[i] = o;
        nb[i] = 1;
      }
      if (a_changed) {
        // Compared and stored as one word: whether the rounded colour moved
        // is noise, a branch on it mispredicts.
        const std::uint32_t v =
            std::uint32_t(cv::saturate_cast<std::uint8_t>(a[i][0])) |
            std::uint32_t(cv::saturate_cast<std::uint8_t>(a[i][1])) << 8 |
            std::uint32_t(cv::saturate_cast<std::uint8_t>(a[i][2])) << 16 |
            0xff000000u;
        std::uint32_t old;
        std::memcpy(&old, out[i].val, 4);
        changed |= v != old;
        std::memcpy(out[i].val, &v, 4);
      }
    }
  }
  if (changed) ++plate_counter_;
  summary_.plate_changed = changed;
  summary_.learned_texels = learned;
  // A texel's evidence never falls back to zero (only Reset clears it), so
  // the known texels are counted as they become known.
  summary_.known_texels = known_texels_;
}

cv::Rect TankWindow(const Camera& camera, const Pose& cam_from_tank,
                    double size_x_m, double size_y_m, double top_m,
                    int pad_px) {
  const cv::Rect image(0, 0, camera.width, camera.height);
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c =
        cam_from_tank * Eigen::Vector3d((i & 1 ? 0.5 : -0.5) * size_x_m,
                                        (i & 2 ? 0.5 : -0.5) * size_y_m,
                                        i & 4 ? top_m : 0.0);
    if (c.z() < 1e-3) return image;
    const double u = camera.fx * c.x() / c.z() + camera.cx;
    const double v = camera.fy * c.y() / c.z() + camera.cy;
    x0 = std::min(x0, u);
    x1 = std::max(x1, u);
    y0 = std::min(y0, v);
    y1 = std::max(y1, v);
  }
  const double lim = 1e6;
  x0 = std::clamp(x0 - pad_px, -lim, lim);
  y0 = std::clamp(y0 - pad_px, -lim, lim);
  x1 = std::clamp(x1 + pad_px, -lim, lim);
  y1 = std::clamp(y1 + pad_px, -lim, lim);
  const cv::Rect r(cv::Point(static_cast<int>(std::floor(x0)),
                             static_cast<int>(std::floor(y0))),
                   cv::Point(static_cast<int>(std::ceil(x1)) + 1,
                             static_cast<int>(std::ceil(y1)) + 1));
  return r & image;
}

void CleanPlate::ClassifyObject(const cv::Mat& frame, const cv::Mat& object,
                                cv::Mat* mask) {
  // The object's pixels marked for learning (255), away from the mask (3 px:
  // an occluder's blurred edge) and 2 px inside the object's own edge (the
  // board's blur).
  cv::Mat& inner = object_inner_;
  cv::Mat& near_mask = object_near_mask_;
  cv::compare(object, 255, inner, cv::CMP_EQ);
  cv::erode(inner, inner, cv::getStructuringElement(cv::MORPH_RECT, {5, 5}));
  cv::dilate(*mask, near_mask,
             cv::getStructuringElement(cv::MORPH_RECT, {7, 7}));
  // An occluder may cover the learning part (a hand over the shaft, which
  // the plate's mask does not reach): the first colour is the median of
  // the part away from the mask, later ones take only pixels the model
  // already accepts.
  const float t_high = static_cast<float>(options_.high_threshold);
  float limit[3];
  for (int c = 0; c < 3; ++c)
    limit[c] = std::max(t_high, 4 * object_spread_[c]);
  auto accepted = [&](const cv::Vec3b& f) {
    for (int c = 0; c < 3; ++c)
      if (std::abs(f[c] - object_colour_[c]) > limit[c]) return false;
    return true;
  };
  // The samples are 8-bit levels: kept as a histogram per channel, whose
  // order statistics are those of the samples themselves.
  int hist[3][256] = {};
  int n = 0;
  for (int y = 0; y < frame.rows; ++y) {
    const cv::Vec3b* f = frame.ptr<cv::Vec3b>(y);
    const std::uint8_t* in = inner.ptr(y);
    const std::uint8_t* nm = near_mask.ptr(y);
    for (int x = 0; x < frame.cols; ++x)
      if (in[x] && !nm[x] && (object_frames_ == 0 || accepted(f[x]))) {
        for (int c = 0; c < 3; ++c) ++hist[c][f[x][c]];
        ++n;
      }
  }
  // The sample of rank n / 2 (0-based) in a histogram.
  auto rank_half = [n](const int* h) {
    int seen = 0, v = 0;
    while (v < 255 && (seen += h[v]) <= n / 2) ++v;
    return v;
  };
  // Learn: median and spread (1.4826 median absolute deviations, a
  // standard deviation for Gaussian noise) of this frame, blended in.
  if (n >= 30) {
    cv::Vec3f med, spread;
    for (int c = 0; c < 3; ++c) {
      const int m = rank_half(hist[c]);
      int dev[256] = {};
      for (int v = 0; v < 256; ++v) dev[std::abs(v - m)] += hist[c][v];
      med[c] = static_cast<float>(m);
      spread[c] = 1.4826f * static_cast<float>(rank_half(dev));
    }
    const float w = object_frames_ == 0 ? 1.0f : 0.2f;
    object_colour_ += w * (med - object_colour_);
    object_spread_ += w * (spread - object_spread_);
    ++object_frames_;
  }
  if (object_frames_ == 0) return;
  // The model as just learned (`accepted` reads the limits and the colour).
  for (int c = 0; c < 3; ++c)
    limit[c] = std::max(t_high, 4 * object_spread_[c]);
  // Classify: the object's own pixels (kObjectBody and up) a pixel inside
  // its outline, far from its colour, are in front of it.
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::Mat& core = object_core_;
  cv::compare(object, kObjectBody, core, cv::CMP_GE);
  cv::erode(core, core, k3);
  for (int y = 0; y < frame.rows; ++y) {
    const cv::Vec3b* f = frame.ptr<cv::Vec3b>(y);
    const std::uint8_t* co = core.ptr(y);
    std::uint8_t* m = mask->ptr(y);
    for (int x = 0; x < frame.cols; ++x)
      if (co[x] && !m[x] && !accepted(f[x])) m[x] = 255;
  }
  // Near an occluder more than a line thin (a hand over the shaft; not a
  // line of the shaft's own pixels that its shading puts off its colour).
  cv::Mat& hand_near = object_hand_near_;
  cv::erode(*mask, hand_near, k3);
  cv::dilate(hand_near, hand_near,
             cv::getStructuringElement(cv::MORPH_RECT, {17, 17}));
  // Its outline's pixels mix it with the board, and the margin round it
  // (kObjectMargin) shows the board where the object's pose is right: a
  // pixel there joins the occluders only when it differs from the object,
  // an occluder reaches it (grown a pixel at a time) and one more than a
  // line thin lies within 8 px (a hand over the shaft covers the outline
  // and the margin beside it too; the board beside a bare shaft is left
  // alone, also where the shaft's own shading puts pixels off its colour).
  for (int step = 0; step < kObjectMarginPx; ++step) {
    cv::dilate(*mask, near_mask, k3);
    bool grew = false;
    for (int y = 0; y < frame.rows; ++y) {
      const cv::Vec3b* f = frame.ptr<cv::Vec3b>(y);
      const std::uint8_t* ob = object.ptr(y);
      const std::uint8_t* co = core.ptr(y);
      const std::uint8_t* hn = hand_near.ptr(y);
      const std::uint8_t* nm = near_mask.ptr(y);
      std::uint8_t* m = mask->ptr(y);
      for (int x = 0; x < frame.cols; ++x)
        if (ob[x] && !co[x] && !m[x] && nm[x] && hn[x] && !accepted(f[x])) {
          m[x] = 255;
          grew = true;
        }
    }
    if (!grew) break;
  }
}

void DrawPenSilhouette(const Camera& camera, const Pose& cam_from_pen,
                       double cube_edge_m, double shaft_radius_m,
                       const Eigen::Vector3d& tip_in_pen, double grow_px,
                       cv::Mat* mask, bool with_cube, double shaft_share) {
  mask->create(camera.height, camera.width, CV_8U);
  mask->setTo(0);
  auto project = [&](const Eigen::Vector3d& p_in_pen, cv::Point2f* px) {
    const Eigen::Vector3d c = cam_from_pen * p_in_pen;
    if (c.z() < 1e-3) return false;
    *px =
        cv::Point2f(static_cast<float>(camera.fx * c.x() / c.z() + camera.cx),
                    static_cast<float>(camera.fy * c.y() / c.z() + camera.cy));
    return true;
  };
  const int grow = std::max(0, static_cast<int>(std::ceil(grow_px)));
  auto fill = [&](const std::vector<cv::Point2f>& pts) {
    if (pts.size() < 3) return;
    std::vector<cv::Point2f> hull;
    cv::convexHull(pts, hull);
    // Fixed-point vertices (4 fractional bits) keep sub-pixel placement.
    std::vector<cv::Point> fixed;
    for (const cv::Point2f& p : hull)
      fixed.emplace_back(cvRound(p.x * 16), cvRound(p.y * 16));
    cv::fillConvexPoly(*mask, fixed, cv::Scalar(255), cv::LINE_8, 4);
    if (grow > 0) {
      const std::vector<std::vector<cv::Point>> ring = {fixed};
      cv::polylines(*mask, ring, true, cv::Scalar(255), 2 * grow + 1,
                    cv::LINE_8, 4);
    }
  };
  // Shaft: rings at the tip and at the cube's -z face (or `shaft_share` of
  // the way there).
  const Eigen::Vector3d face(0, 0, -0.5 * cube_edge_m);
  const Eigen::Vector3d top = tip_in_pen + shaft_share * (face - tip_in_pen);
  const Eigen::Vector3d axis = (face - tip_in_pen).normalized();
  const Eigen::Vector3d u = axis.unitOrthogonal(), v = axis.cross(u);
  std::vector<cv::Point2f> shaft;
  for (int i = 0; i < 16; ++i) {
    const double a = 2 * M_PI * i / 16;
    const Eigen::Vector3d off =
        shaft_radius_m * (std::cos(a) * u + std::sin(a) * v);
    cv::Point2f p;
    if (project(tip_in_pen + off, &p)) shaft.push_back(p);
    if (project(top + off, &p)) shaft.push_back(p);
  }
  fill(shaft);
  if (!with_cube) return;
  std::vector<cv::Point2f> cube;
  const double h = 0.5 * cube_edge_m;
  for (int i = 0; i < 8; ++i) {
    cv::Point2f p;
    if (project({(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h}, &p))
      cube.push_back(p);
  }
  fill(cube);
}

void DrawPenPlateMasks(const Camera& camera, const Pose& cam_from_pen,
                       double cube_edge_m, double shaft_radius_m,
                       const Eigen::Vector3d& tip_in_pen, double margin_m,
                       cv::Mat* exclude, cv::Mat* object) {
  const double depth = std::max(0.05, cam_from_pen.translation.z());
  const double grow_px = margin_m * camera.fx / depth;
  DrawPenSilhouette(camera, cam_from_pen, cube_edge_m, shaft_radius_m,
                    tip_in_pen, grow_px, exclude);
  DrawPenSilhouette(camera, cam_from_pen, cube_edge_m, shaft_radius_m,
                    tip_in_pen, grow_px, object, /*with_cube=*/false);
  cv::Mat body, lower;
  DrawPenSilhouette(camera, cam_from_pen, cube_edge_m, shaft_radius_m,
                    tip_in_pen, 0.0, &body, /*with_cube=*/false);
  DrawPenSilhouette(camera, cam_from_pen, cube_edge_m, shaft_radius_m,
                    tip_in_pen, 0.0, &lower, /*with_cube=*/false,
                    /*shaft_share=*/0.5);
  object->setTo(CleanPlate::kObjectMargin, *object);
  object->setTo(CleanPlate::kObjectBody, body);
  object->setTo(CleanPlate::kObjectLearn, lower);
}

}  // namespace ripple::tracking
