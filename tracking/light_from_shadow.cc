#include "tracking/light_from_shadow.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "geometry/polygon2d.h"
#include "tracking/clean_plate.h"

namespace ripple::tracking {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kDeg = M_PI / 180;
constexpr double kInf = std::numeric_limits<double>::infinity();

// 8-bit level -> linear light in [0, 1] under the camera's transfer.
std::array<float, 256> DecodeTable(geometry::Transfer transfer) {
  std::array<float, 256> t{};
  for (int i = 0; i < 256; ++i) {
    const double v = i / 255.0;
    if (transfer == geometry::Transfer::kLinear) {
      t[i] = static_cast<float>(v);
    } else {  // IEC 61966-2-1
      t[i] = static_cast<float>(
          v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    }
  }
  return t;
}

// Bilinear value of an N-channel float image at (x, y) (pixel centres at
// integers); false outside or next to an invalid (NaN) value.
template <int N>
bool SampleFloat(const cv::Mat& img, double x, double y, float* out) {
  const int x0 = static_cast<int>(std::floor(x));
  const int y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= img.cols || y0 + 1 >= img.rows)
    return false;
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  const float* r0 = img.ptr<float>(y0) + N * x0;
  const float* r1 = img.ptr<float>(y0 + 1) + N * x0;
  for (int c = 0; c < N; ++c) {
    out[c] = (1 - fy) * ((1 - fx) * r0[c] + fx * r0[N + c]) +
             fy * ((1 - fx) * r1[c] + fx * r1[N + c]);
    if (std::isnan(out[c])) return false;
  }
  return true;
}

// The board resampled in tank coordinates: the centre of texel (i, j) is
// tank (x, y) = centre0 + texel * (i, j); NaN where not measured. Per
// texel: log brightness (the mean of B, G and R, linear), and the
// chromaticity log(B / G), log(R / G); all relative to the reference when
// there is one.
struct BoardGrid {
  Vector2d centre0 = Vector2d::Zero();
  double texel = 0;
  cv::Mat brightness;  // CV_32F
  cv::Mat chroma;      // CV_32FC2

  bool At(const Vector2d& p, float* v) const {
    return SampleFloat<1>(brightness, (p.x() - centre0.x()) / texel,
                          (p.y() - centre0.y()) / texel, v);
  }
  bool ChromaAt(const Vector2d& p, float* c) const {
    return SampleFloat<2>(chroma, (p.x() - centre0.x()) / texel,
                          (p.y() - centre0.y()) / texel, c);
  }
};

// Linear BGR (CV_32FC3) of an 8-bit BGR or BGRA image; NaN where a BGRA
// image's alpha is not 255.
cv::Mat LinearBgr(const cv::Mat& img, const std::array<float, 256>& decode) {
  cv::Mat out(img.rows, img.cols, CV_32FC3);
  const int channels = img.channels();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int y = 0; y < img.rows; ++y) {
    const uint8_t* s = img.ptr<uint8_t>(y);
    float* d = out.ptr<float>(y);
    for (int x = 0; x < img.cols; ++x, s += channels, d += 3) {
      const bool known = channels != 4 || s[3] == 255;
      for (int c = 0; c < 3; ++c) d[c] = known ? decode[s[c]] : nan;
    }
  }
  return out;
}

// Log brightness and chromaticity of linear BGR.
void LogColour(const float* bgr, float* brightness, float* chroma) {
  constexpr float kFloor = 1e-4f;
  const float b = std::max(bgr[0], kFloor), g = std::max(bgr[1], kFloor),
              r = std::max(bgr[2], kFloor);
  *brightness = std::log((b + g + r) * (1.0f / 3));
  chroma[0] = std::log(b / g);
  chroma[1] = std::log(r / g);
}

void BuildGrid(const LightFromShadowOptions& options, const Camera& camera,
               const PenSpec& pen, const LightFromShadowInput& input,
               BoardGrid* grid) {
  const std::array<float, 256> decode = DecodeTable(camera.transfer);
  const cv::Mat frame = LinearBgr(input.bgr, decode);
  cv::Mat reference;
  if (input.reference && !input.reference->bgra.empty())
    reference = LinearBgr(input.reference->bgra, decode);
  cv::Mat pen_mask;
  DrawPenSilhouette(camera, input.cam_from_tank * input.tank_from_pen,
                    pen.cube_edge_m, pen.shaft_radius_m, pen.tip_in_pen,
                    options.pen_grow_px, &pen_mask);
  const bool use_exclude = !input.exclude.empty() &&
                           input.exclude.type() == CV_8U &&
                           input.exclude.size() == pen_mask.size();

  const Eigen::AlignedBox2d& box = input.board_in_tank;
  grid->texel = options.texel_m;
  const int w = std::max(1, static_cast<int>(box.sizes().x() / grid->texel));
  const int h = std::max(1, static_cast<int>(box.sizes().y() / grid->texel));
  grid->centre0 = box.min() + Vector2d::Constant(0.5 * grid->texel);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  grid->brightness.create(h, w, CV_32F);
  grid->brightness.setTo(nan);
  grid->chroma.create(h, w, CV_32FC2);
  grid->chroma.setTo(cv::Scalar::all(nan));
  const Eigen::Matrix3d r = input.cam_from_tank.R();
  const Vector3d& t = input.cam_from_tank.translation;
  for (int j = 0; j < h; ++j) {
    float* bright = grid->brightness.ptr<float>(j);
    float* chroma = grid->chroma.ptr<float>(j);
    for (int i = 0; i < w; ++i) {
      const Vector2d p = grid->centre0 + grid->texel * Vector2d(i, j);
      const Vector3d c = r.col(0) * p.x() + r.col(1) * p.y() + t;
      if (c.z() < 1e-3) continue;
      // The pen's silhouette and `exclude` are ideal-pinhole masks.
      const int iu =
          static_cast<int>(std::lround(camera.fx * c.x() / c.z() + camera.cx));
      const int iv =
          static_cast<int>(std::lround(camera.fy * c.y() / c.z() + camera.cy));
      if (iu >= 0 && iv >= 0 && iu < pen_mask.cols && iv < pen_mask.rows &&
          (pen_mask.at<uint8_t>(iv, iu) ||
           (use_exclude && input.exclude.at<uint8_t>(iv, iu))))
        continue;
      const Vector2d px = camera.Project(c);
      float bgr[3], v, ch[2];
      if (!SampleFloat<3>(frame, px.x(), px.y(), bgr)) continue;
      LogColour(bgr, &v, ch);
      if (!reference.empty()) {
        const BoardReference& ref = *input.reference;
        float ref_bgr[3], ref_v, ref_ch[2];
        if (!SampleFloat<3>(
                reference, (p.x() - ref.origin_m.x()) / ref.texel_m - 0.5,
                (p.y() - ref.origin_m.y()) / ref.texel_m - 0.5, ref_bgr))
          continue;
        LogColour(ref_bgr, &ref_v, ref_ch);
        v -= ref_v;
        ch[0] -= ref_ch[0];
        ch[1] -= ref_ch[1];
      }
      bright[i] = v;
      chroma[2 * i] = ch[0];
      chroma[2 * i + 1] = ch[1];
    }
  }
}

// The pen in the tank frame.
struct PenInTank {
  Vector3d tip, base, centre;  // base: centre of the cube's -z face
  std::array<Vector3d, 8> corners;
  Vector3d axis;  // tip -> cube
  double radius = 0;
  // Points around the shaft's two end circles.
  std::array<Vector3d, 16> tip_rim, base_rim;
};

PenInTank MakePen(const PenSpec& pen, const Pose& tank_from_pen) {
  PenInTank p;
  const double h = 0.5 * pen.cube_edge_m;
  p.tip = tank_from_pen * pen.tip_in_pen;
  p.base = tank_from_pen * Vector3d(0, 0, -h);
  p.centre = tank_from_pen.translation;
  for (int i = 0; i < 8; ++i)
    p.corners[i] = tank_from_pen *
                   Vector3d(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
  p.axis = (p.base - p.tip).normalized();
  p.radius = pen.shaft_radius_m;
  // A tip tracked below the board casts from where the shaft meets it.
  constexpr double kMinHeight = 1e-4;
  if (p.tip.z() < kMinHeight && p.base.z() > kMinHeight)
    p.tip += p.axis * ((kMinHeight - p.tip.z()) / p.axis.z());
  const Vector3d a = p.axis.unitOrthogonal(), b = p.axis.cross(a);
  for (size_t k = 0; k < p.tip_rim.size(); ++k) {
    const double t = 2 * M_PI * k / p.tip_rim.size();
    const Vector3d off = p.radius * (std::cos(t) * a + std::sin(t) * b);
    p.tip_rim[k] = p.tip + off;
    p.base_rim[k] = p.base + off;
  }
  return p;
}

// Shadow of a point along `l` (unit, l_z > 0) onto z = 0.
Vector2d ShadowOf(const Vector3d& x, const Vector3d& l) {
  return x.head<2>() - (x.z() / l.z()) * l.head<2>();
}

// Parameter interval [*lo, *hi] of the line p + s d inside a counter-
// clockwise convex polygon (Cyrus-Beck); false if it misses.
bool ClipLine(const std::vector<Vector2d>& poly, const Vector2d& p,
              const Vector2d& d, double* lo, double* hi) {
  if (poly.size() < 3) return false;
  double a = -kInf, b = kInf;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vector2d e = poly[i] - poly[j];
    // Inside: cross(e, x - poly[j]) >= 0 with x = p + s d.
    const double c0 = e.x() * (p - poly[j]).y() - e.y() * (p - poly[j]).x();
    const double c1 = e.x() * d.y() - e.y() * d.x();
    if (std::abs(c1) < 1e-15) {
      if (c0 < 0) return false;
      continue;
    }
    const double s = -c0 / c1;
    if (c1 > 0) {
      a = std::max(a, s);
    } else {
      b = std::min(b, s);
    }
  }
  if (a > b) return false;
  *lo = a;
  *hi = b;
  return true;
}

// A convex outline with its extent in the line's coordinates (t along the
// line from its origin, s across it).
struct Outline {
  std::vector<Vector2d> poly;  // counter-clockwise
  double t0 = 0, t1 = 0, s0 = 0, s1 = 0;

  void Bound(const Vector2d& origin, const Vector2d& u, const Vector2d& perp) {
    t0 = s0 = kInf;
    t1 = s1 = -kInf;
    for (const Vector2d& q : poly) {
      const double t = (q - origin).dot(u), s = (q - origin).dot(perp);
      t0 = std::min(t0, t);
      t1 = std::max(t1, t);
      s0 = std::min(s0, s);
      s1 = std::max(s1, s);
    }
  }
  // Whether the point at line coordinates (t, s) is at least `d` outside
  // the bounds (then it is at least `d` outside the outline).
  bool Beyond(double t, double s, double d) const {
    return t < t0 - d || t > t1 + d || s < s0 - d || s > s1 + d;
  }
};

// A candidate's predicted shadow on the board plane.
struct PredictedShadow {
  Vector2d start;           // the shadow of the tip's centre: the line's origin
  Vector2d u, perp;         // along the line (away from the tip), across it
  double shaft_length = 0;  // to the shadow of the cube's -z face
  double half_width = 0;    // of the shaft's shadow, across the line
  // Between these line parameters the shaft's shadow is the band of
  // `half_width` (its ends' ellipses lie outside).
  double band_t0 = 0, band_t1 = 0;
  // The shaft's (the hull of the shadows of its two end circles) and the
  // cube's.
  Outline shaft, cube;
  double begin = 0, end = 0;  // the line's parameters where it enters, leaves
  // Penumbra: half-width per metre of height of the occluding point.
  double penumbra_per_height = 0;
  double tip_height = 0, base_height = 0, centre_height = 0;

  double Penumbra(double t) const {
    const double h = t >= shaft_length
                         ? centre_height
                         : tip_height + std::clamp(t / shaft_length, 0.0, 1.0) *
                                            (base_height - tip_height);
    return h * penumbra_per_height;
  }
  // Whether p, at line coordinates (t, s), is at least `d` outside the
  // predicted shadow.
  bool Outside(const Vector2d& p, double t, double s, double d) const {
    return (shaft.Beyond(t, s, d) ||
            geometry::SignedDistanceToConvexPolygon(shaft.poly, p) >= d) &&
           (cube.Beyond(t, s, d) ||
            geometry::SignedDistanceToConvexPolygon(cube.poly, p) >= d);
  }
  // The predicted shadow's extent across the line at parameter t: [*lo,
  // *hi]; false if it misses there.
  bool Across(double t, double* lo, double* hi) const {
    *lo = kInf;
    *hi = -kInf;
    const Vector2d p = start + t * u;
    double a, b;
    if (t >= band_t0 && t <= band_t1) {
      *lo = -half_width;
      *hi = half_width;
    } else if (t >= shaft.t0 && t <= shaft.t1 &&
               ClipLine(shaft.poly, p, perp, &a, &b)) {
      *lo = a;
      *hi = b;
    }
    if (t >= cube.t0 && t <= cube.t1 && ClipLine(cube.poly, p, perp, &a, &b)) {
      *lo = std::min(*lo, a);
      *hi = std::max(*hi, b);
    }
    return *lo <= *hi;
  }
};

bool Predict(const PenInTank& pen, const Vector3d& l, double tan_light,
             PredictedShadow* s) {
  s->start = ShadowOf(pen.tip, l);
  const Vector2d along = ShadowOf(pen.base, l) - s->start;
  s->shaft_length = along.norm();
  // A light (nearly) along the shaft casts a blob, not a line.
  if (s->shaft_length < 4 * pen.radius) return false;
  s->u = along / s->shaft_length;
  s->perp = Vector2d(-s->u.y(), s->u.x());
  // The band's edges are the shadows of the axis moved by the radius
  // across both the axis and the light.
  const Vector3d n = pen.axis.cross(l);
  if (n.norm() < 1e-6) return false;
  const Vector3d offset = pen.radius * n.normalized();
  const Vector2d offset_shadow =
      offset.head<2>() - (offset.z() / l.z()) * l.head<2>();
  s->half_width = std::abs(offset_shadow.dot(s->perp));
  std::vector<Vector2d>& rims = s->shaft.poly;
  rims.clear();
  s->band_t0 = -kInf;
  s->band_t1 = kInf;
  for (size_t k = 0; k < pen.tip_rim.size(); ++k) {
    rims.push_back(ShadowOf(pen.tip_rim[k], l));
    s->band_t0 = std::max(s->band_t0, (rims.back() - s->start).dot(s->u));
    rims.push_back(ShadowOf(pen.base_rim[k], l));
    s->band_t1 = std::min(s->band_t1, (rims.back() - s->start).dot(s->u));
  }
  rims = geometry::ConvexHull(std::move(rims));
  s->cube.poly.clear();
  for (const Vector3d& c : pen.corners) s->cube.poly.push_back(ShadowOf(c, l));
  s->cube.poly = geometry::ConvexHull(std::move(s->cube.poly));
  s->shaft.Bound(s->start, s->u, s->perp);
  s->cube.Bound(s->start, s->u, s->perp);
  double lo, hi;
  s->begin = 0;
  s->end = s->shaft_length;
  if (ClipLine(s->shaft.poly, s->start, s->u, &lo, &hi)) {
    s->begin = std::min(s->begin, lo);
    s->end = std::max(s->end, hi);
  }
  if (ClipLine(s->cube.poly, s->start, s->u, &lo, &hi))
    s->end = std::max(s->end, hi);
  s->penumbra_per_height = tan_light / l.z();
  s->tip_height = pen.tip.z();
  s->base_height = pen.base.z();
  s->centre_height = pen.centre.z();
  return true;
}

double Median(std::vector<double>* v) {
  if (v->empty()) return 0;
  const size_t m = v->size() / 2;
  std::nth_element(v->begin(), v->begin() + m, v->end());
  return (*v)[m];
}

struct CandidateScore {
  double score = -kInf;  // -inf: not enough of the shadow is measurable
  double median_darkness = 0;
  double dark_fraction = 0;
  int inside = 0, ends = 0;
};

Vector3d Direction(double azimuth, double elevation) {
  return {std::cos(elevation) * std::cos(azimuth),
          std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

class Scorer {
 public:
  Scorer(const LightFromShadowOptions& options, const BoardGrid& grid,
         const PenInTank& pen)
      : options_(options),
        grid_(grid),
        pen_(pen),
        tan_light_(std::tan(options.light_radius_rad)) {}

  int evaluated() const { return evaluated_; }

  // `step`: sample spacing along the line, metres; `min_inside`: fewer
  // measurable samples inside the shadow score -inf; `coarse`: the umbra's
  // middle alone, which widens the score's peak across the line for the
  // coarse grid.
  CandidateScore Score(double azimuth, double elevation, double step,
                       int min_inside, bool coarse) {
    return Score(Direction(azimuth, elevation), step, min_inside, coarse);
  }
  CandidateScore Score(const Vector3d& light, double step, int min_inside,
                       bool coarse) {
    ++evaluated_;
    CandidateScore out;
    PredictedShadow& s = shadow_;
    if (!Predict(pen_, light, tan_light_, &s)) return out;
    inside_.clear();
    ends_.clear();
    spread_ = 0;
    const double gap = options_.side_gap_m;
    // Inside: points of the line with umbra across them; the darkness of
    // the umbra's middle and (unless `coarse`) its two edges against the lit
    // board beyond.
    const float tol = static_cast<float>(options_.side_tolerance);
    // The coarse grid looks at no more than kCoarseSamples points of a long
    // shadow (and as many beyond each end), enough to find its basin.
    constexpr int kCoarseSamples = 40;
    if (coarse) step = std::max(step, (s.end - s.begin) / kCoarseSamples);
    for (double t = s.begin + 0.5 * step; t < s.end; t += step) {
      double lo, hi;
      if (!s.Across(t, &lo, &hi)) continue;
      const double penumbra = s.Penumbra(t);
      const double margin = penumbra + options_.edge_margin_m;
      if (!(lo <= -margin && hi >= margin)) continue;
      // Nor within the penumbra of the shadow's ends.
      if (t - s.begin < margin || s.end - t < margin) continue;
      const Vector2d p = s.start + t * s.u;
      float c, ol, orr;
      if (!grid_.At(p, &c) ||
          !grid_.At(p + (hi + gap + penumbra) * s.perp, &ol) ||
          !grid_.At(p + (lo - gap - penumbra) * s.perp, &orr))
        continue;
      double lit;
      if (!LitReference(p, p + (hi + gap + penumbra) * s.perp, ol,
                        p + (lo - gap - penumbra) * s.perp, orr, &lit))
        continue;
      if (coarse) {
        inside_.push_back(Clamp(lit - c));
        continue;
      }
      // Uniform across the umbra, or texture.
      float il, ir;
      if (!grid_.At(p + (hi - margin) * s.perp, &il) ||
          !grid_.At(p + (lo + margin) * s.perp, &ir))
        continue;
      const double spread = std::max({c, il, ir}) - std::min({c, il, ir});
      if (spread > tol) continue;
      inside_.push_back(Clamp(lit - (c + il + ir) / 3.0));
      spread_ += std::min(1.0, spread / options_.darkness_threshold);
    }
    if (static_cast<int>(inside_.size()) < min_inside) return out;
    // Beyond the ends, from just outside their penumbra: lit, with lit board
    // beside.
    const double side = s.half_width + gap;
    auto end_stretch = [&](double t0, double dir) {
      for (double k = 0.5 * step; k < options_.end_length_m; k += step) {
        const double t = t0 + dir * k;
        const Vector2d p = s.start + t * s.u;
        const double penumbra = s.Penumbra(t);
        const double w = side + penumbra;
        if (!s.Outside(p, t, 0, options_.edge_margin_m + penumbra) ||
            !s.Outside(p + w * s.perp, t, w, 0.5 * gap) ||
            !s.Outside(p - w * s.perp, t, -w, 0.5 * gap))
          continue;
        float c, a, b;
        double lit;
        if (!grid_.At(p, &c) || !grid_.At(p + w * s.perp, &a) ||
            !grid_.At(p - w * s.perp, &b) ||
            !LitReference(p, p + w * s.perp, a, p - w * s.perp, b, &lit))
          continue;
        ends_.push_back(Clamp(lit - c));
      }
    };
    end_stretch(s.begin - options_.edge_margin_m - s.Penumbra(s.begin), -1.0);
    end_stretch(s.end + options_.edge_margin_m + s.Penumbra(s.end), 1.0);

    // Votes: a sample counts +1 for the candidate when it is as dark as
    // expected (inside) or lit (beyond the ends), -1 when the opposite,
    // linearly between: bounded, so that no printed ink outweighs a shadow.
    const double tau = options_.darkness_threshold;
    auto vote = [tau](double x) { return std::clamp(x / tau, -1.0, 1.0); };
    double score = 0;
    int dark = 0;
    for (double d : inside_) {
      score += vote(d - tau);
      dark += d > tau;
    }
    for (double d : ends_) score += vote(tau - d);
    // An umbra that is not uniform across (one edge sample in the penumbra
    // or lit) loses up to half a vote: this centres the line on the shadow.
    score -= 0.5 * spread_;
    // In votes per fine sample step: a length of board, whatever the step.
    out.score = score * step / options_.sample_step_m;
    out.inside = static_cast<int>(inside_.size());
    out.ends = static_cast<int>(ends_.size());
    out.dark_fraction = double(dark) / inside_.size();
    out.median_darkness = Median(&inside_);
    return out;
  }

 private:
  // Whether the board at `p` has the chromaticity of the board at `lit`
  // (within `chroma_tolerance`).
  bool SameColour(const Vector2d& p, const Vector2d& lit) const {
    float a[2], b[2];
    if (!grid_.ChromaAt(p, a) || !grid_.ChromaAt(lit, b)) return false;
    const double d0 = a[0] - b[0], d1 = a[1] - b[1];
    return d0 * d0 + d1 * d1 <=
           options_.chroma_tolerance * options_.chroma_tolerance;
  }

  // The lit board's log brightness for a sample at `p` from its two sides
  // (positions and values): the brighter of the sides of p's colour (print
  // only darkens; a shadow keeps the board's colour, a hand does not).
  // False when neither side has p's colour.
  bool LitReference(const Vector2d& p, const Vector2d& left, float left_value,
                    const Vector2d& right, float right_value,
                    double* lit) const {
    const bool l = SameColour(p, left), r = SameColour(p, right);
    if (!l && !r) return false;
    *lit = l && r ? std::max(left_value, right_value)
                  : (l ? left_value : right_value);
    return true;
  }

  // Darkness (log brightness of lit board minus that of the sample),
  // clamped to what a shadow can be (an ambient share of 0.05..1 and
  // somewhat brighter).
  static double Clamp(double d) { return std::clamp(d, -1.0, 3.0); }

  const LightFromShadowOptions& options_;
  const BoardGrid& grid_;
  const PenInTank& pen_;
  double tan_light_;
  int evaluated_ = 0;
  std::vector<double> inside_, ends_;
  double spread_ = 0;       // summed umbra non-uniformity, in thresholds
  PredictedShadow shadow_;  // reused: its outlines keep their storage
};

double AngleBetween(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace

bool LightFromShadowOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = std::string("light from shadow: ") + m;
    return false;
  };
  if (!(min_elevation_rad > 0.01 && max_elevation_rad < 0.5 * M_PI - 0.01 &&
        min_elevation_rad < max_elevation_rad))
    return fail("elevations must satisfy 0.01 < min < max < pi/2 - 0.01");
  if (!(coarse_step_rad >= 0.5 * kDeg && coarse_step_rad <= 20 * kDeg))
    return fail("coarse step must be 0.5-20 degrees");
  if (!(final_step_rad > 0 && final_step_rad <= coarse_step_rad))
    return fail("final step must be in (0, coarse step]");
  if (refine_seeds < 1 || refine_seeds > 64)
    return fail("refine seeds must be 1-64");
  if (!(texel_m >= 2e-4 && texel_m <= 0.01))
    return fail("texel must be 0.2-10 mm");
  if (!(sample_step_m >= 2e-4 && sample_step_m <= 0.02))
    return fail("sample step must be 0.2-20 mm");
  if (!(side_gap_m >= 0 && side_gap_m <= 0.05))
    return fail("side gap must be 0-50 mm");
  if (!(end_length_m >= 0 && end_length_m <= 0.2))
    return fail("end length must be 0-200 mm");
  if (!(light_radius_rad >= 0 && light_radius_rad < 0.2))
    return fail("light radius must be in [0, 0.2) rad");
  if (!(side_tolerance > 0)) return fail("side tolerance must be positive");
  if (!(chroma_tolerance > 0)) return fail("chroma tolerance must be positive");
  if (!(pen_grow_px >= 0 && pen_grow_px <= 50))
    return fail("pen grow must be 0-50 px");
  if (!(min_contrast > 0 && min_contrast < 1))
    return fail("minimum contrast must be in (0, 1)");
  if (!(edge_margin_m >= 0 && edge_margin_m <= 0.05))
    return fail("edge margin must be 0-50 mm");
  if (!(darkness_threshold > 0 && darkness_threshold < 3))
    return fail("darkness threshold must be in (0, 3)");
  if (!(min_score >= 0)) return fail("minimum score must be >= 0");
  if (!(min_dark_fraction >= 0 && min_dark_fraction <= 1))
    return fail("minimum dark fraction must be in [0, 1]");
  if (min_shadow_samples < 2)
    return fail("minimum shadow samples must be >= 2");
  if (!(ridge_step_rad > 0 && ridge_step_rad <= coarse_step_rad))
    return fail("ridge step must be in (0, coarse step]");
  if (!(ridge_tolerance >= 0 && ridge_tolerance_share >= 0 &&
        ridge_tolerance_share < 1))
    return fail("ridge tolerances must be >= 0 (the share below 1)");
  if (!(uncertainty_score_share > 0 && uncertainty_score_share < 1))
    return fail("uncertainty score share must be in (0, 1)");
  return true;
}

const char* ToString(LightStatus status) {
  switch (status) {
    case LightStatus::kFound:
      return "found";
    case LightStatus::kBadInput:
      return "bad input";
    case LightStatus::kNoShadowOnBoard:
      return "no shadow on the board";
    case LightStatus::kTooWeak:
      return "shadow too weak";
  }
  return "?";
}

void PenShadowLine(const PenSpec& pen, const Pose& tank_from_pen,
                   const Vector3d& light_in_tank, Vector2d* tip_shadow,
                   Vector2d* cube_shadow) {
  const PenInTank p = MakePen(pen, tank_from_pen);
  const Vector3d l = light_in_tank.normalized();
  *tip_shadow = ShadowOf(p.tip, l);
  *cube_shadow = ShadowOf(p.centre, l);
}

bool EstimateLightFromShadow(const LightFromShadowOptions& options,
                             const Camera& camera, const PenSpec& pen,
                             const LightFromShadowInput& input,
                             LightEstimate* estimate) {
  *estimate = LightEstimate();
  if (input.bgr.type() != CV_8UC3 || input.bgr.cols != camera.width ||
      input.bgr.rows != camera.height || input.board_in_tank.isEmpty() ||
      input.cam_from_tank.Inverse().translation.z() <= 0 ||
      (input.reference && (input.reference->bgra.type() != CV_8UC4 ||
                           !(input.reference->texel_m > 0)))) {
    estimate->status = LightStatus::kBadInput;
    return false;
  }
  BoardGrid grid;
  BuildGrid(options, camera, pen, input, &grid);
  const PenInTank pen_in_tank = MakePen(pen, input.tank_from_pen);
  Scorer scorer(options, grid, pen_in_tank);

  // 1. Coarse grid: rings of equal elevation, each with azimuths `step`
  // apart on the sphere (fewer towards the zenith).
  const double step = options.coarse_step_rad;
  struct Cell {
    double az, el, score;
  };
  const int n_el =
      1 + static_cast<int>(std::floor(
              (options.max_elevation_rad - options.min_elevation_rad) / step));
  std::vector<int> ring_start(n_el + 1, 0), ring_size(n_el, 0);
  std::vector<Cell> coarse;
  const double coarse_sample = 2 * options.sample_step_m;
  const int coarse_min = std::max(2, options.min_shadow_samples / 2);
  for (int j = 0; j < n_el; ++j) {
    const double el = options.min_elevation_rad + j * step;
    ring_size[j] = std::max(
        8, static_cast<int>(std::lround(2 * M_PI * std::cos(el) / step)));
    ring_start[j] = static_cast<int>(coarse.size());
    for (int i = 0; i < ring_size[j]; ++i) {
      const double az = 2 * M_PI * i / ring_size[j];
      coarse.push_back(
          {az, el,
           scorer.Score(az, el, coarse_sample, coarse_min, true).score});
    }
  }
  ring_start[n_el] = static_cast<int>(coarse.size());

  // 2. Its local maxima (against the two ring neighbours and the three
  // nearest cells of each adjacent ring), best first.
  auto cell_at = [&](int j, double az) -> const Cell& {
    const int n = ring_size[j];
    int i = static_cast<int>(std::lround(az / (2 * M_PI) * n));
    i = ((i % n) + n) % n;
    return coarse[ring_start[j] + i];
  };
  std::vector<std::pair<double, int>> seeds;
  for (int j = 0; j < n_el; ++j) {
    const int n = ring_size[j];
    for (int i = 0; i < n; ++i) {
      const Cell& c = coarse[ring_start[j] + i];
      if (!std::isfinite(c.score)) continue;
      bool is_max = coarse[ring_start[j] + (i + 1) % n].score <= c.score &&
                    coarse[ring_start[j] + (i + n - 1) % n].score <= c.score;
      for (int jj = j - 1; jj <= j + 1 && is_max; jj += 2) {
        if (jj < 0 || jj >= n_el) continue;
        const double da = 2 * M_PI / ring_size[jj];
        for (int k = -1; k <= 1 && is_max; ++k)
          is_max = cell_at(jj, c.az + k * da).score <= c.score;
      }
      if (is_max) seeds.emplace_back(c.score, ring_start[j] + i);
    }
  }
  if (seeds.empty()) {
    estimate->status = LightStatus::kNoShadowOnBoard;
    estimate->candidates = scorer.evaluated();
    return false;
  }
  std::sort(seeds.begin(), seeds.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });
  if (static_cast<int>(seeds.size()) > options.refine_seeds)
    seeds.resize(options.refine_seeds);

  // 3. Pattern search from each seed at the fine sample spacing.
  double best_az = 0, best_el = 0;
  CandidateScore best;
  for (const auto& seed : seeds) {
    double az = coarse[seed.second].az;
    double el = coarse[seed.second].el;
    CandidateScore here = scorer.Score(az, el, options.sample_step_m,
                                       options.min_shadow_samples, false);
    for (double s = 0.5 * step; s >= options.final_step_rad;) {
      const double s_az = s / std::max(std::cos(el), 0.1);
      double next_az = az, next_el = el;
      CandidateScore next = here;
      for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
          if (!di && !dj) continue;
          const double e = std::clamp(el + dj * s, options.min_elevation_rad,
                                      options.max_elevation_rad);
          const double a = az + di * s_az;
          const CandidateScore c = scorer.Score(
              a, e, options.sample_step_m, options.min_shadow_samples, false);
          if (c.score > next.score) {
            next = c;
            next_az = a;
            next_el = e;
          }
        }
      }
      if (next.score > here.score) {
        here = next;
        az = next_az;
        el = next_el;
      } else {
        s *= 0.5;
      }
    }
    if (here.score > best.score) {
      best = here;
      best_az = az;
      best_el = el;
    }
  }
  estimate->candidates = scorer.evaluated();
  if (!std::isfinite(best.score)) {
    estimate->status = LightStatus::kNoShadowOnBoard;
    return false;
  }
  // 4. Along the ridge: every light in the plane of the shaft's axis and
  // the best casts the same shadow line, only its ends move. Where the ends
  // are not seen the score is flat along it; the estimate is the middle of
  // the stretch that scores within `ridge_tolerance` of the best.
  Vector3d light = Direction(best_az, best_el);
  double ridge_half = 0;
  {
    const Vector3d a1 = pen_in_tank.axis;
    const Vector3d off_axis = light - light.dot(a1) * a1;
    if (off_axis.norm() > 1e-3) {
      const Vector3d a2 = off_axis.normalized();
      const double phi0 = std::atan2(light.dot(a2), light.dot(a1));
      const double dphi = options.ridge_step_rad;
      auto at = [&](double phi) {
        return Vector3d(std::cos(phi) * a1 + std::sin(phi) * a2);
      };
      auto in_range = [&](const Vector3d& l) {
        const double el = std::asin(std::clamp(l.z(), -1.0, 1.0));
        return el >= options.min_elevation_rad - 1e-9 &&
               el <= options.max_elevation_rad + 1e-9;
      };
      const double tolerance = std::max(
          options.ridge_tolerance, options.ridge_tolerance_share * best.score);
      // Walk out both ways while the score stays near the best so far.
      std::vector<std::pair<double, CandidateScore>> walk = {{phi0, best}};
      double top = best.score;
      for (int dir = -1; dir <= 1; dir += 2) {
        for (int k = 1; k < 1000; ++k) {
          const double phi = phi0 + dir * k * dphi;
          const Vector3d l = at(phi);
          if (!in_range(l)) break;
          const CandidateScore c = scorer.Score(
              l, options.sample_step_m, options.min_shadow_samples, false);
          if (!(c.score >= top - tolerance)) break;
          top = std::max(top, c.score);
          walk.emplace_back(phi, c);
        }
      }
      // The stretch of the final top around its best point.
      std::sort(walk.begin(), walk.end(),
                [](const auto& x, const auto& y) { return x.first < y.first; });
      size_t arg = 0;
      for (size_t i = 0; i < walk.size(); ++i)
        if (walk[i].second.score > walk[arg].second.score) arg = i;
      size_t lo = arg, hi = arg;
      while (lo > 0 && walk[lo - 1].second.score >= top - tolerance) --lo;
      while (hi + 1 < walk.size() &&
             walk[hi + 1].second.score >= top - tolerance)
        ++hi;
      const double mid = 0.5 * (walk[lo].first + walk[hi].first);
      // The sample nearest the middle, for its measurements.
      size_t m = lo;
      for (size_t i = lo; i <= hi; ++i)
        if (std::abs(walk[i].first - mid) < std::abs(walk[m].first - mid))
          m = i;
      best = walk[m].second;
      light = at(walk[m].first);
      ridge_half = 0.5 * (walk[hi].first - walk[lo].first);
    }
  }
  best_az = std::atan2(light.y(), light.x());
  if (best_az < 0) best_az += 2 * M_PI;
  best_el = std::asin(std::clamp(light.z(), -1.0, 1.0));
  estimate->candidates = scorer.evaluated();
  estimate->light_in_tank = light;
  estimate->azimuth_rad = best_az;
  estimate->elevation_rad = best_el;
  estimate->shadow_ratio = std::exp(-best.median_darkness);
  estimate->ambient_share = estimate->shadow_ratio;
  estimate->contrast = 1 - estimate->shadow_ratio;
  estimate->score = best.score;
  estimate->dark_fraction = best.dark_fraction;
  estimate->shadow_samples = best.inside;
  estimate->end_samples = best.ends;

  // 5. How far from the estimate the ridge, and the coarse grid, still
  // score nearly as well.
  const double best_coarse =
      scorer.Score(best_az, best_el, coarse_sample, coarse_min, true).score;
  const double threshold = options.uncertainty_score_share * best_coarse;
  double uncertainty = ridge_half;
  for (const Cell& c : coarse)
    if (c.score >= threshold)
      uncertainty =
          std::max(uncertainty, AngleBetween(light, Direction(c.az, c.el)));
  estimate->uncertainty_rad = uncertainty;

  if (!(estimate->contrast >= options.min_contrast &&
        best.score >= options.min_score &&
        best.dark_fraction >= options.min_dark_fraction &&
        best.inside >= options.min_shadow_samples)) {
    estimate->status = LightStatus::kTooWeak;
    return false;
  }
  estimate->status = LightStatus::kFound;
  const double score_term = std::clamp(
      options.min_score > 0 ? best.score / options.min_score - 1.0 : 1.0, 0.0,
      1.0);
  const double unc_term =
      std::clamp((20 * kDeg - uncertainty) / (17 * kDeg), 0.0, 1.0);
  estimate->confidence = score_term * unc_term;
  return true;
}

bool LightTrackerOptions::IsValid(std::string* error) const {
  auto fail = [&](const char* m) {
    if (error) *error = std::string("light tracker: ") + m;
    return false;
  };
  if (window < 1 || window > 1000) return fail("window must be 1-1000");
  if (min_estimates < 1 || min_estimates > window)
    return fail("minimum estimates must be 1-window");
  if (!(min_confidence >= 0 && min_confidence <= 1))
    return fail("minimum confidence must be in [0, 1]");
  if (!(inlier_angle_rad > 0 && inlier_angle_rad < M_PI))
    return fail("inlier angle must be in (0, pi)");
  if (hold_frames < 0) return fail("hold frames must be >= 0");
  return true;
}

LightTracker::LightTracker(const LightTrackerOptions& options)
    : options_(options) {}

void LightTracker::Reset() {
  window_.clear();
  current_.reset();
  frames_since_estimate_ = 0;
}

const std::optional<TrackedLight>& LightTracker::Update(
    const LightEstimate& estimate) {
  if (estimate.found() && estimate.confidence >= options_.min_confidence) {
    window_.push_back(
        {estimate.light_in_tank.normalized(), estimate.ambient_share});
    while (static_cast<int>(window_.size()) > options_.window)
      window_.pop_front();
    frames_since_estimate_ = 0;
    Recompute();
    return current_;
  }
  ++frames_since_estimate_;
  if (current_) {
    current_->frames_since_estimate = frames_since_estimate_;
    if (options_.hold_frames > 0 &&
        frames_since_estimate_ > options_.hold_frames)
      Reset();
  }
  return current_;
}

void LightTracker::Recompute() {
  if (static_cast<int>(window_.size()) < options_.min_estimates) return;
  const size_t n = window_.size();
  size_t medoid = 0;
  double least = kInf;
  for (size_t i = 0; i < n; ++i) {
    double sum = 0;
    for (size_t j = 0; j < n; ++j)
      sum += AngleBetween(window_[i].light_in_tank, window_[j].light_in_tank);
    if (sum < least) {
      least = sum;
      medoid = i;
    }
  }
  Vector3d mean = Vector3d::Zero();
  std::vector<double> shares;
  for (const Entry& e : window_) {
    if (AngleBetween(e.light_in_tank, window_[medoid].light_in_tank) >
        options_.inlier_angle_rad)
      continue;
    mean += e.light_in_tank;
    shares.push_back(e.ambient_share);
  }
  TrackedLight light;
  light.light_in_tank = mean.normalized();
  light.ambient_share = Median(&shares);
  light.estimates = static_cast<int>(n);
  light.inliers = static_cast<int>(shares.size());
  std::vector<double> angles;
  for (const Entry& e : window_)
    if (AngleBetween(e.light_in_tank, window_[medoid].light_in_tank) <=
        options_.inlier_angle_rad)
      angles.push_back(AngleBetween(e.light_in_tank, light.light_in_tank));
  light.spread_rad = Median(&angles);
  light.frames_since_estimate = 0;
  current_ = light;
}

}  // namespace ripple::tracking
