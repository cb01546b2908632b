#include "tracking/clean_plate.h"

#include <algorithm>
#include <cmath>
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
  if (min_region_px < 0) return fail("minimum region must be >= 0");
  return true;
}

CleanPlate::CleanPlate(const Camera& camera, double tank_size_x_m,
                       double tank_size_y_m, const CleanPlateOptions& options)
    : camera_(camera), options_(options) {
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
  plate_bgra_ = cv::Mat::zeros(plate_h_, plate_w_, CV_8UC4);
  foreground_.setTo(0);
  last_foreground_.release();
  window_ = cv::Rect();
  gain_ = 1.0;
  ++plate_counter_;
  summary_ = CleanPlateSummary();
}

bool CleanPlate::SetBoardPrior(const cv::Mat& design_levels,
                               const cv::Mat& valid) {
  if (design_levels.type() != CV_32FC3 || valid.type() != CV_8U ||
      design_levels.size() != plate_size() || valid.size() != plate_size())
    return false;
  prior_.create(plate_h_, plate_w_, CV_32FC4);
  for (int j = 0; j < plate_h_; ++j) {
    const cv::Vec3f* d = design_levels.ptr<cv::Vec3f>(j);
    const std::uint8_t* v = valid.ptr(j);
    cv::Vec4f* out = prior_.ptr<cv::Vec4f>(j);
    for (int i = 0; i < plate_w_; ++i)
      out[i] = cv::Vec4f(d[i][0], d[i][1], d[i][2], v[i] ? 255.0f : 0.0f);
  }
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
                                             cv::Rect window) {
  summary_ = CleanPlateSummary();
  // The last window's mask is cleared; the new one is written below.
  if (window_.area() > 0) foreground_(window_).setTo(0);
  window &= cv::Rect(0, 0, camera_.width, camera_.height);
  window_ = window;
  if (bgr.type() != CV_8UC3 || bgr.cols != camera_.width ||
      bgr.rows != camera_.height || window.area() <= 0) {
    window_ = cv::Rect();
    last_foreground_.release();
    return summary_;
  }
  // The plate's corners must lie in front of the camera, or the homography
  // folds the board behind it into the image.
  const cv::Matx33d image_from_board = ImageFromBoard(camera_, cam_from_tank);
  const double s = options_.texel_m;
  const cv::Matx33d board_from_plate(s, 0, origin_m_.x + 0.5 * s, 0, s,
                                     origin_m_.y + 0.5 * s, 0, 0, 1);
  const cv::Matx33d window_from_image(1, 0, -window.x, 0, 1, -window.y, 0, 0,
                                      1);
  const cv::Matx33d window_from_plate =
      window_from_image * image_from_board * board_from_plate;
  for (int c = 0; c < 4; ++c) {
    const cv::Vec3d corner((c & 1) ? plate_w_ : 0, (c & 2) ? plate_h_ : 0, 1);
    if ((image_from_board * board_from_plate * corner)[2] <= 1e-6) {
      window_ = cv::Rect();
      last_foreground_.release();
      return summary_;
    }
  }
  cv::Mat frame;
  Undistort(bgr, window, &frame);
  cv::Mat plate_in_window;
  cv::warpPerspective(plate_bgra_, plate_in_window, window_from_plate,
                      window.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                      cv::Scalar::all(0));
  cv::Mat prior_in_window;
  if (!prior_.empty())
    cv::warpPerspective(prior_, prior_in_window, window_from_plate,
                        window.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                        cv::Scalar::all(0));
  cv::Mat exclude_in_window;
  if (!exclude.empty()) exclude_in_window = exclude(window);
  if (last_foreground_.size() != window.size()) last_foreground_.release();
  EstimateGains(frame, plate_in_window, prior_in_window, exclude_in_window);
  Classify(frame, plate_in_window, prior_in_window, exclude_in_window);
  Learn(frame, exclude_in_window, window_from_plate);
  summary_.gain = gain_;
  return summary_;
}

void CleanPlate::EstimateGains(const cv::Mat& frame, const cv::Mat& plate,
                               const cv::Mat& prior, const cv::Mat& exclude) {
  // The plate's gain: the median ratio of frame to plate brightness over
  // known, bright enough board pixels (tag black carries no exposure
  // information); the design's: per channel over its paper.
  const int w = frame.cols, h = frame.rows;
  std::vector<float> ratios, prior_ratios[3];
  ratios.reserve(static_cast<size_t>(w * h / 4 + 1));
  for (int y = 0; y < h; y += 2) {
    const cv::Vec3b* f = frame.ptr<cv::Vec3b>(y);
    const cv::Vec4b* p = plate.ptr<cv::Vec4b>(y);
    const cv::Vec4f* q = prior.empty() ? nullptr : prior.ptr<cv::Vec4f>(y);
    const std::uint8_t* ex = exclude.empty() ? nullptr : exclude.ptr(y);
    const std::uint8_t* last =
        last_foreground_.empty() ? nullptr : last_foreground_.ptr(y);
    for (int x = 0; x < w; x += 2) {
      if ((ex && ex[x]) || (last && last[x])) continue;
      if (p[x][3] == 255) {
        const int sp = p[x][0] + p[x][1] + p[x][2];
        if (sp >= 90)
          ratios.push_back(static_cast<float>(f[x][0] + f[x][1] + f[x][2]) /
                           static_cast<float>(sp));
      }
      if (q && q[x][3] == 255 && q[x][0] > 150 && q[x][1] > 150 &&
          q[x][2] > 150) {
        for (int c = 0; c < 3; ++c)
          prior_ratios[c].push_back(f[x][c] / q[x][c]);
      }
    }
  }
  auto median = [](std::vector<float>* v) {
    auto mid = v->begin() + v->size() / 2;
    std::nth_element(v->begin(), mid, v->end());
    return std::clamp(*mid, 0.25f, 4.0f);
  };
  if (ratios.size() >= 200) gain_ = median(&ratios);
  if (prior_ratios[0].size() >= 200)
    for (int c = 0; c < 3; ++c) prior_gain_[c] = median(&prior_ratios[c]);
}

namespace {

// Largest excess of `f` over the range [lo, hi], 8-bit levels.
inline float Excess(const cv::Vec3f& f, const cv::Vec3f& lo,
                    const cv::Vec3f& hi) {
  float d = 0;
  for (int c = 0; c < 3; ++c) d = std::max({d, lo[c] - f[c], f[c] - hi[c]});
  return d;
}

// Distance (largest channel) of `f` from the colour segment lo-hi: the
// mixtures a pixel straddling the neighbourhood's darkest and brightest
// colours can take. (A box test on the channel ranges would accept any
// colour between a black tag cell and white paper, a hand included.)
inline float SegmentDistance(const cv::Vec3f& f, const cv::Vec3f& lo,
                             const cv::Vec3f& hi) {
  const cv::Vec3f d = hi - lo;
  const float dd = d.dot(d);
  const float t = dd > 0 ? std::clamp((f - lo).dot(d) / dd, 0.0f, 1.0f) : 0.0f;
  const cv::Vec3f r = f - (lo + t * d);
  return std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
}

// A shadow on `q`: darker by a common factor of at least `min_ratio`, the
// chromaticity kept within `chroma_tol` of the brightness (+ `noise`).
inline bool IsShadow(const cv::Vec3f& f, const cv::Vec3f& q, float min_ratio,
                     float chroma_tol, float noise) {
  const float qq = q.dot(q);
  if (!(qq > 0)) return false;
  const float a = f.dot(q) / qq;
  if (!(a >= min_ratio && a < 1.0f)) return false;
  const cv::Vec3f r = f - a * q;
  const float res = std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
  return res <= chroma_tol * a * std::max({q[0], q[1], q[2]}) + noise;
}

}  // namespace

bool CleanPlate::PriorAllows(const cv::Vec3f& o, const cv::Vec3f& p) const {
  // The light may change the brightness, not the colour: the brightness
  // ratio within the illumination range, and the chromaticity kept. Shadows
  // are not allowed: a texel learns its colour in the light, and grey
  // mixtures of a dark object's edge with paper read as shadow.
  const cv::Vec3f q = p.mul(prior_gain_);
  const float lo = static_cast<float>(options_.illumination_low);
  const float hi = static_cast<float>(options_.illumination_high);
  const float t_low = static_cast<float>(options_.low_threshold);
  if (Excess(o, lo * q, hi * q) > t_low) return false;
  const float qq = q.dot(q);
  if (!(qq > 0)) return true;
  const float a = o.dot(q) / qq;
  const cv::Vec3f r = o - a * q;
  const float res = std::max({std::abs(r[0]), std::abs(r[1]), std::abs(r[2])});
  return res <= static_cast<float>(options_.shadow_chroma_tolerance) * a *
                        std::max({q[0], q[1], q[2]}) +
                    0.25f * t_low;
}

void CleanPlate::Classify(const cv::Mat& frame, const cv::Mat& plate,
                          const cv::Mat& prior, const cv::Mat& exclude) {
  const int w = frame.cols, h = frame.rows;
  const cv::Mat k3 = cv::getStructuringElement(cv::MORPH_RECT, {3, 3});
  cv::Mat lo, hi, prior_lo, prior_hi;
  cv::erode(plate, lo, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  cv::dilate(plate, hi, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  if (!prior.empty()) {
    cv::erode(prior, prior_lo, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
    cv::dilate(prior, prior_hi, k3, {-1, -1}, 1, cv::BORDER_REPLICATE);
  }
  const float g = static_cast<float>(gain_);
  const cv::Vec3f& pg = prior_gain_;
  const float ill_lo = static_cast<float>(options_.illumination_low);
  const float ill_hi = static_cast<float>(options_.illumination_high);
  const float t_low = static_cast<float>(options_.low_threshold);
  const float t_high = static_cast<float>(options_.high_threshold);
  const float min_ratio = static_cast<float>(options_.shadow_min_ratio);
  const float chroma_tol = static_cast<float>(options_.shadow_chroma_tolerance);
  cv::Mat weak(h, w, CV_8U), strong(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    const cv::Vec3b* f8 = frame.ptr<cv::Vec3b>(y);
    const cv::Vec4b* p = plate.ptr<cv::Vec4b>(y);
    const cv::Vec4b* pl = lo.ptr<cv::Vec4b>(y);
    const cv::Vec4b* ph = hi.ptr<cv::Vec4b>(y);
    const cv::Vec4f* q = prior.empty() ? nullptr : prior.ptr<cv::Vec4f>(y);
    const cv::Vec4f* ql = prior.empty() ? nullptr : prior_lo.ptr<cv::Vec4f>(y);
    const cv::Vec4f* qh = prior.empty() ? nullptr : prior_hi.ptr<cv::Vec4f>(y);
    const std::uint8_t* ex = exclude.empty() ? nullptr : exclude.ptr(y);
    const std::uint8_t* last =
        last_foreground_.empty() ? nullptr : last_foreground_.ptr(y);
    std::uint8_t* wk = weak.ptr(y);
    std::uint8_t* st = strong.ptr(y);
    for (int x = 0; x < w; ++x) {
      wk[x] = st[x] = 0;
      if (ex && ex[x]) continue;
      const cv::Vec3f f(f8[x][0], f8[x][1], f8[x][2]);
      cv::Vec3f e_lo, e_hi, centre;
      float shadow_ratio = min_ratio;
      if (pl[x][3] == 255) {
        // The learned plate, known over the whole neighbourhood.
        e_lo = g * cv::Vec3f(pl[x][0], pl[x][1], pl[x][2]);
        e_hi = g * cv::Vec3f(ph[x][0], ph[x][1], ph[x][2]);
        centre = g * cv::Vec3f(p[x][0], p[x][1], p[x][2]);
      } else if (q && ql[x][3] == 255) {
        // Not learned yet: the printed design under this frame's light.
        e_lo = ill_lo * cv::Vec3f(ql[x][0], ql[x][1], ql[x][2]).mul(pg);
        e_hi = ill_hi * cv::Vec3f(qh[x][0], qh[x][1], qh[x][2]).mul(pg);
        centre = cv::Vec3f(q[x][0], q[x][1], q[x][2]).mul(pg);
        shadow_ratio *= ill_lo;
      } else {
        continue;
      }
      const float d = SegmentDistance(f, e_lo, e_hi);
      if (d <= t_low) continue;
      if (IsShadow(f, centre, shadow_ratio, chroma_tol, 0.5f * t_low)) continue;
      wk[x] = 255;
      if (d > t_high || (last && last[x])) st[x] = 255;
    }
  }
  // Spatial hysteresis: weak regions holding a strong pixel, big enough.
  cv::Mat labels, stats, centroids;
  const int n =
      cv::connectedComponentsWithStats(weak, labels, stats, centroids, 8);
  std::vector<std::uint8_t> keep(static_cast<size_t>(n), 0);
  for (int y = 0; y < h; ++y) {
    const int* l = labels.ptr<int>(y);
    const std::uint8_t* st = strong.ptr(y);
    for (int x = 0; x < w; ++x)
      if (st[x]) keep[static_cast<size_t>(l[x])] = 1;
  }
  keep[0] = 0;
  for (int i = 1; i < n; ++i)
    if (stats.at<int>(i, cv::CC_STAT_AREA) < options_.min_region_px)
      keep[static_cast<size_t>(i)] = 0;
  cv::Mat mask(h, w, CV_8U);
  for (int y = 0; y < h; ++y) {
    const int* l = labels.ptr<int>(y);
    std::uint8_t* m = mask.ptr(y);
    for (int x = 0; x < w; ++x) m[x] = keep[static_cast<size_t>(l[x])] * 255;
  }
  cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, k3, {-1, -1}, 1,
                   cv::BORDER_CONSTANT, cv::Scalar::all(0));
  if (!exclude.empty()) mask.setTo(0, exclude);
  mask.copyTo(foreground_(window_));
  last_foreground_ = mask;
  summary_.foreground_px = cv::countNonZero(mask);
}

void CleanPlate::Learn(const cv::Mat& frame, const cv::Mat& exclude,
                       const cv::Matx33d& window_from_plate) {
  // The frame with alpha 255 where it may teach the plate; 128 where it
  // only feeds the challengers (foreground and 2 pixels around it: the
  // blurred edge of an occluder mixes it with the board); 0 at known objects
  // and 2 pixels around them. Warped onto the plate.
  cv::Mat frame_bgra;
  cv::cvtColor(frame, frame_bgra, cv::COLOR_BGR2BGRA);
  const cv::Mat k5 = cv::getStructuringElement(cv::MORPH_RECT, {5, 5});
  if (!last_foreground_.empty()) {
    cv::Mat grown;
    cv::dilate(last_foreground_, grown, k5);
    std::vector<cv::Mat> ch;
    cv::split(frame_bgra, ch);
    ch[3].setTo(128, grown);
    cv::merge(ch, frame_bgra);
  }
  if (!exclude.empty()) {
    cv::Mat grown;
    cv::dilate(exclude, grown, k5);
    frame_bgra.setTo(cv::Scalar(0, 0, 0, 0), grown);
  }
  cv::Mat seen;
  cv::warpPerspective(frame_bgra, seen, window_from_plate,
                      cv::Size(plate_w_, plate_h_),
                      cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                      cv::BORDER_CONSTANT, cv::Scalar::all(0));
  const float inv_g = static_cast<float>(1.0 / gain_);
  const float tol = static_cast<float>(options_.low_threshold) * inv_g;
  const float rate = static_cast<float>(options_.learn_rate);
  const int cap = options_.evidence_cap_frames;
  const int takeover = options_.takeover_frames;
  int learned = 0, known = 0;
  bool changed = false;
  for (int j = 0; j < plate_h_; ++j) {
    const cv::Vec4b* o8 = seen.ptr<cv::Vec4b>(j);
    cv::Vec3f* a = background_.ptr<cv::Vec3f>(j);
    cv::Vec3f* b = challenger_.ptr<cv::Vec3f>(j);
    std::uint16_t* na = background_n_.ptr<std::uint16_t>(j);
    std::uint16_t* nb = challenger_n_.ptr<std::uint16_t>(j);
    cv::Vec4b* out = plate_bgra_.ptr<cv::Vec4b>(j);
    const cv::Vec4f* design =
        prior_.empty() ? nullptr : prior_.ptr<cv::Vec4f>(j);
    for (int i = 0; i < plate_w_; ++i) {
      if (o8[i][3] >= 100) {
        const cv::Vec3f o(o8[i][0] * inv_g, o8[i][1] * inv_g, o8[i][2] * inv_g);
        // Colours the printed design rules out are never board; pixels at
        // an occluder only feed the challenger.
        const bool design_ok =
            !design || design[i][3] != 255 ||
            PriorAllows(cv::Vec3f(o8[i][0], o8[i][1], o8[i][2]),
                        cv::Vec3f(design[i][0], design[i][1], design[i][2]));
        const bool learn = o8[i][3] >= 250 && design_ok;
        if (learn) ++learned;
        if (na[i] == 0) {
          if (learn) {
            a[i] = o;
            na[i] = 1;
          }
        } else if (MaxAbs3(o, a[i]) <= tol) {
          if (learn) {
            a[i] += rate * (o - a[i]);
            na[i] = static_cast<std::uint16_t>(std::min<int>(cap, na[i] + 1));
            if (nb[i] > 0) --nb[i];
          }
        } else if (nb[i] > 0 && MaxAbs3(o, b[i]) <= tol) {
          b[i] += (o - b[i]) * (1.0f / (nb[i] + 1));
          nb[i] = static_cast<std::uint16_t>(
              std::min<int>(std::max(cap, takeover) + 1, nb[i] + 1));
          if (nb[i] > na[i] && nb[i] >= takeover && design_ok) {
            std::swap(a[i], b[i]);
            na[i] = nb[i];
            nb[i] = 0;
          }
        } else {
          b[i] = o;
          nb[i] = 1;
        }
        if (na[i] > 0) {
          const cv::Vec4b v(cv::saturate_cast<std::uint8_t>(a[i][0]),
                            cv::saturate_cast<std::uint8_t>(a[i][1]),
                            cv::saturate_cast<std::uint8_t>(a[i][2]), 255);
          if (v != out[i]) {
            out[i] = v;
            changed = true;
          }
        }
      }
      if (na[i] > 0) ++known;
    }
  }
  if (changed) ++plate_counter_;
  summary_.plate_changed = changed;
  summary_.learned_texels = learned;
  summary_.known_texels = known;
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

void DrawPenSilhouette(const Camera& camera, const Pose& cam_from_pen,
                       double cube_edge_m, double shaft_radius_m,
                       const Eigen::Vector3d& tip_in_pen, double grow_px,
                       cv::Mat* mask) {
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
  // Shaft: rings at the tip and at the cube's -z face.
  const Eigen::Vector3d top(0, 0, -0.5 * cube_edge_m);
  const Eigen::Vector3d axis = (top - tip_in_pen).normalized();
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
  std::vector<cv::Point2f> cube;
  const double h = 0.5 * cube_edge_m;
  for (int i = 0; i < 8; ++i) {
    cv::Point2f p;
    if (project({(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h}, &p))
      cube.push_back(p);
  }
  fill(cube);
}

}  // namespace ripple::tracking
