#include "tracking/tag_detector.h"

#include <apriltag.h>
#include <common/image_u8.h>
#include <common/zarray.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <unordered_map>

#include "geometry/check.h"
#include "tracking/bilinear.h"
#include "tracking/tag_family.h"

namespace ripple::tracking {

double TagDetection::SizePx() const {
  double sum = 0;
  for (int k = 0; k < 4; ++k) sum += (corners[(k + 1) % 4] - corners[k]).norm();
  return 0.25 * sum;
}

bool TagDetectorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!TagFamily::Create(family))
    return fail("unknown tag family '" + family + "'");
  if (!(quad_decimate >= 1.0 && quad_decimate <= 8.0))
    return fail("quad_decimate must be in [1, 8]");
  if (!(quad_sigma >= 0.0)) return fail("quad_sigma must be >= 0");
  if (threads < 1 || threads > 64) return fail("threads must be in [1, 64]");
  if (max_hamming < 0 || max_hamming > 2)
    return fail("max_hamming must be 0, 1 or 2");
  if (min_white_black_diff < 0 || min_white_black_diff > 255)
    return fail("min_white_black_diff must be in [0, 255]");
  if (!(min_decision_margin >= 0.0))
    return fail("min_decision_margin must be >= 0");
  if (!(std::abs(pixel_offset_px) <= 2.0 && std::abs(edge_outward_px) <= 2.0))
    return fail("corner corrections must be within 2 px");
  if (lens && !lens->IsValid(error)) return false;
  return edge_fit_limits.IsValid(error);
}

bool EdgeFitLimits::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (!(max_shift_px > 0 && max_shift_px <= 10))
    return fail("edge fit: max_shift_px must be in (0, 10]");
  if (!(margin_share >= 0 && margin_share <= 1))
    return fail("edge fit: margin_share must be in [0, 1]");
  if (!(max_occluded_shift_cells >= 0 && max_occluded_shift_cells <= 8))
    return fail("edge fit: max_occluded_shift_cells must be in [0, 8]");
  return true;
}

std::array<Eigen::Vector2d, 4> CorrectCorners(
    const std::array<Eigen::Vector2d, 4>& raw, double pixel_offset_px,
    double edge_outward_px) {
  std::array<Eigen::Vector2d, 4> out;
  const Eigen::Vector2d offset(pixel_offset_px, pixel_offset_px);
  for (int k = 0; k < 4; ++k) out[k] = raw[k] - offset;
  if (edge_outward_px == 0.0) return out;
  const Eigen::Vector2d centre = 0.25 * (out[0] + out[1] + out[2] + out[3]);
  // Outward unit normal of edge k (corner k -> k+1).
  std::array<Eigen::Vector2d, 4> normal;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = out[k], b = out[(k + 1) % 4];
    Eigen::Vector2d n(b.y() - a.y(), a.x() - b.x());
    const double len = n.norm();
    if (len < 1e-9) return out;
    n /= len;
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    normal[k] = n;
  }
  std::array<Eigen::Vector2d, 4> shifted = out;
  for (int k = 0; k < 4; ++k) {
    // Corner k lies on edges k-1 and k; move it so that both lines shift
    // outward by edge_outward_px.
    Eigen::Matrix2d m;
    m.row(0) = normal[(k + 3) % 4].transpose();
    m.row(1) = normal[k].transpose();
    const double det = m.determinant();
    if (std::abs(det) < 1e-6) continue;
    shifted[k] = out[k] + m.inverse() *
                              Eigen::Vector2d(edge_outward_px, edge_outward_px);
  }
  return shifted;
}

namespace {

struct Line {
  Eigen::Vector2d point, dir;  // dir is unit
  // The foot of the perpendicular from x.
  Eigen::Vector2d Project(const Eigen::Vector2d& x) const {
    return point + dir.dot(x - point) * dir;
  }
};

constexpr int kSteps = 12;  // a profile's intervals across the edge

// One profile across an edge: kSteps + 1 samples from centre - hw n to
// centre + hw n, the window re-centred on the edge.
struct EdgeProfile {
  Eigen::Vector2d centre;
  double t =
      0;  // position along the edge: 0 at its first corner, 1 at its last
  double hw = 0;
  double v[kSteps + 1];
  double Dark() const { return 0.5 * (v[0] + v[1]); }
  double Bright() const { return 0.5 * (v[kSteps - 1] + v[kSteps]); }
};

// The rising crossing of `mid` nearest the window's centre, as a signed
// distance along n from it; false when there is none.
bool Crossing(const EdgeProfile& f, double mid, double* r) {
  const double step = 2 * f.hw / kSteps;
  double best = 1e9;
  for (int j = 0; j < kSteps; ++j) {
    if ((f.v[j] < mid) != (f.v[j + 1] < mid) && f.v[j + 1] > f.v[j]) {
      const double x =
          -f.hw + (j + (mid - f.v[j]) / (f.v[j + 1] - f.v[j])) * step;
      if (std::abs(x) < std::abs(best)) best = x;
    }
  }
  if (best > 1e8) return false;
  *r = best;
  return true;
}

// The profile across an edge at `centre` along n, half_width hw.
bool SampleProfile(const cv::Mat& g, const Eigen::Vector2d& centre,
                   const Eigen::Vector2d& n, double hw, EdgeProfile* f) {
  f->centre = centre;
  f->hw = hw;
  const double step = 2 * hw / kSteps;
  for (int j = 0; j <= kSteps; ++j) {
    const Eigen::Vector2d q = centre + (-hw + j * step) * n;
    if (!SampleBilinear(g, q.x(), q.y(), &f->v[j])) return false;
  }
  return true;
}

Eigen::Vector2d ToIdeal(const LensPixels* lens, const Eigen::Vector2d& pixel) {
  return lens ? lens->ToIdeal(pixel) : pixel;
}
Eigen::Vector2d ToImage(const LensPixels* lens, const Eigen::Vector2d& ideal) {
  return lens ? lens->ToImage(ideal) : ideal;
}

// The share of an edge its profiles span.
double Support(const std::vector<EdgeProfile>& profiles) {
  if (profiles.empty()) return 0;
  const auto [lo, hi] = std::minmax_element(
      profiles.begin(), profiles.end(),
      [](const EdgeProfile& a, const EdgeProfile& b) { return a.t < b.t; });
  return hi->t - lo->t;
}

// How many profiles an edge of `length` pixels is read at.
int SamplesAlongEdge(double length) {
  return std::clamp(static_cast<int>(length / 3), 5, 16);
}

// Profiles across the edge a -> b with outward normal n; see FitTagEdges.
// Each is centred on the mid-level crossing of its own dark and bright ends
// (three passes: the first looks wider, for a coarse corner). The positions
// (EdgeProfile::t) of profiles that leave the image or find no edge go to
// `failed`.
std::vector<EdgeProfile> SampleEdge(const cv::Mat& g, const Eigen::Vector2d& a,
                                    const Eigen::Vector2d& b,
                                    const Eigen::Vector2d& n, double half_width,
                                    std::vector<double>* failed) {
  const int samples = SamplesAlongEdge((b - a).norm());
  std::vector<EdgeProfile> out;
  out.reserve(samples);
  for (int i = 0; i < samples; ++i) {
    EdgeProfile f;
    f.t = 0.12 + 0.76 * (i + 0.5) / samples;
    f.centre = a + f.t * (b - a);
    bool ok = false;
    for (int pass = 0; pass < 3; ++pass) {
      ok =
          SampleProfile(g, f.centre, n,
                        pass == 0 ? std::max(half_width, 2.0) : half_width, &f);
      if (!ok) break;
      double r = 0;
      ok = f.Bright() - f.Dark() >= 10 &&
           Crossing(f, 0.5 * (f.Dark() + f.Bright()), &r);
      if (!ok) break;
      if (pass < 2) f.centre += r * n;  // re-centre the window, then refine
    }
    if (ok) {
      out.push_back(f);
    } else {
      failed->push_back(f.t);
    }
  }
  return out;
}

// A robust line through `points` (a second fit without the points far from
// the first: a blemish, an occluding edge); false with fewer than 4 points.
bool FitLine(std::vector<Eigen::Vector2d> points, Line* line) {
  if (points.size() < 4) return false;
  for (int iteration = 0; iteration < 2; ++iteration) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : points) mean += p;
    mean /= points.size();
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    line->point = mean;
    line->dir = eig.eigenvectors().col(1);
    if (iteration == 1) break;
    const Eigen::Vector2d normal(-line->dir.y(), line->dir.x());
    std::vector<double> dist;
    for (const auto& p : points) dist.push_back(std::abs(normal.dot(p - mean)));
    std::vector<double> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                     sorted.end());
    const double limit = std::max(0.3, 3.0 * sorted[sorted.size() / 2]);
    std::vector<Eigen::Vector2d> kept;
    for (size_t i = 0; i < points.size(); ++i)
      if (dist[i] <= limit) kept.push_back(points[i]);
    if (kept.size() < 4) return false;
    points.swap(kept);
  }
  return true;
}

// Whether cell c (0 .. width_at_border - 1) of the black border along edge
// k (corner k -> k + 1, corners TL, TR, BR, BL of the tag image) has a
// black cell inside it.
bool InnerCellBlack(const TagBitmap& bitmap, int k, int c) {
  const int w = bitmap.width_at_border;
  const int lo = (bitmap.total_width - w) / 2, hi = lo + w - 1;
  int row = 0, col = 0;
  switch (k) {
    case 0:
      row = lo + 1;
      col = lo + c;
      break;  // top, left to right
    case 1:
      row = lo + c;
      col = hi - 1;
      break;  // right, top to bottom
    case 2:
      row = hi - 1;
      col = hi - c;
      break;  // bottom, right to left
    default:
      row = hi - c;
      col = lo + 1;
      break;  // left, bottom to top
  }
  return bitmap.black(row, col);
}

// The mean of two samples at `offsets` along n from p; false off the image.
bool SamplePair(const cv::Mat& g, const Eigen::Vector2d& p,
                const Eigen::Vector2d& n, double o1, double o2, double* v) {
  double v1 = 0, v2 = 0;
  const Eigen::Vector2d q1 = p + o1 * n, q2 = p + o2 * n;
  if (!SampleBilinear(g, q1.x(), q1.y(), &v1) ||
      !SampleBilinear(g, q2.x(), q2.y(), &v2))
    return false;
  *v = 0.5 * (v1 + v2);
  return true;
}

// The tag's black as a share of the white beside it, read on the fitted
// `lines` (ok[k]: edge k has one) at the middle of every border cell with a
// black cell inside it (see FitTagEdges); nullopt with fewer than 3 such
// cells.
std::optional<double> BorderBlackRatio(
    const cv::Mat& gray, const TagBitmap& bitmap,
    const std::array<Eigen::Vector2d, 4>& corners,
    const std::array<Eigen::Vector2d, 4>& normals,
    const std::array<Line, 4>& lines, const std::array<bool, 4>& ok,
    double half_width, const LensPixels* lens) {
  const int w = bitmap.width_at_border;
  const double step = 2 * half_width / kSteps;
  // Per black-backed cell, the dark and white ends summed over three
  // points along the cell's middle; the tag's ratio is that of the sums
  // over the cells whose own ratio is not an outlier (a blemish, a glare),
  // which averages the noise of every sample: an error of the shared
  // ratio moves all four edges together, which is a distance error.
  std::vector<std::array<double, 2>> cells;  // dark, white sums
  for (int k = 0; k < 4; ++k) {
    if (!ok[k]) continue;
    const Eigen::Vector2d a = corners[k], b = corners[(k + 1) % 4];
    const Eigen::Vector2d n = normals[k];
    for (int c = 1; c + 1 < w; ++c) {
      if (!InnerCellBlack(bitmap, k, c)) continue;
      std::array<double, 2> sum{0, 0};
      bool good = true;
      for (double f : {0.3, 0.5, 0.7}) {
        const Eigen::Vector2d guess = a + (c + f) / w * (b - a);
        const Eigen::Vector2d q =
            ToImage(lens, lines[k].Project(ToIdeal(lens, guess)));
        double dark = 0, bright = 0;
        good = good &&
               SamplePair(gray, q, n, -half_width, -half_width + step, &dark) &&
               SamplePair(gray, q, n, half_width, half_width - step, &bright);
        sum[0] += dark;
        sum[1] += bright;
      }
      if (good && sum[1] - sum[0] >= 30) cells.push_back(sum);
    }
  }
  if (cells.size() < 3) return std::nullopt;
  std::vector<double> ratios;
  for (const auto& c : cells) ratios.push_back(c[0] / c[1]);
  std::vector<double> sorted = ratios;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2,
                   sorted.end());
  const double median = sorted[sorted.size() / 2];
  std::vector<double> deviation;
  for (double r : ratios) deviation.push_back(std::abs(r - median));
  std::nth_element(deviation.begin(), deviation.begin() + deviation.size() / 2,
                   deviation.end());
  const double limit = 3 * 1.4826 * deviation[deviation.size() / 2] + 1e-3;
  double dark_sum = 0, white_sum = 0;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (std::abs(ratios[i] - median) > limit) continue;
    dark_sum += cells[i][0];
    white_sum += cells[i][1];
  }
  return dark_sum / white_sum;
}

}  // namespace

cv::Mat DecodeToLinearLut(geometry::Transfer transfer) {
  cv::Mat lut(1, 256, CV_8U);
  for (int i = 0; i < 256; ++i) {
    const double v = i / 255.0;
    const double l = transfer == geometry::Transfer::kLinear ? v
                     : v <= 0.04045                          ? v / 12.92
                                    : std::pow((v + 0.055) / 1.055, 2.4);
    lut.at<uint8_t>(i) = cv::saturate_cast<uint8_t>(std::lround(255.0 * l));
  }
  return lut;
}

LensPixels::LensPixels(const geometry::CameraModel& lens) : lens_(lens) {
  cols_ = (lens.width + 2 * kMarginPx) / kStepPx + 2;
  rows_ = (lens.height + 2 * kMarginPx) / kStepPx + 2;
  table_.resize(static_cast<size_t>(cols_) * rows_);
  for (int r = 0; r < rows_; ++r)
    for (int c = 0; c < cols_; ++c)
      table_[r * cols_ + c] = ToIdealExact(
          Eigen::Vector2d(c * kStepPx - kMarginPx, r * kStepPx - kMarginPx));
}

Eigen::Vector2d LensPixels::ToIdealExact(const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d n = lens_.UndistortToNormalized(pixel);
  return {lens_.fx * n.x() + lens_.cx, lens_.fy * n.y() + lens_.cy};
}

Eigen::Vector2d LensPixels::ToIdeal(const Eigen::Vector2d& pixel) const {
  const double u = (pixel.x() + kMarginPx) / kStepPx;
  const double v = (pixel.y() + kMarginPx) / kStepPx;
  const int c = static_cast<int>(std::floor(u)),
            r = static_cast<int>(std::floor(v));
  if (!(c >= 0 && r >= 0 && c + 1 < cols_ && r + 1 < rows_))
    return ToIdealExact(pixel);
  const double fu = u - c, fv = v - r;
  const Eigen::Vector2d* t = &table_[r * cols_ + c];
  return (1 - fv) * ((1 - fu) * t[0] + fu * t[1]) +
         fv * ((1 - fu) * t[cols_] + fu * t[cols_ + 1]);
}

Eigen::Vector2d LensPixels::ToImage(const Eigen::Vector2d& ideal) const {
  return lens_.Project(Eigen::Vector3d((ideal.x() - lens_.cx) / lens_.fx,
                                       (ideal.y() - lens_.cy) / lens_.fy, 1.0));
}

EdgeFit FitTagEdges(const cv::Mat& gray,
                    const std::array<Eigen::Vector2d, 4>& corners,
                    double cell_px, const EdgeFitLimits& limits,
                    const TagBitmap* bitmap, const LensPixels* lens) {
  EdgeFit fit;
  fit.corners = corners;
  const Eigen::Vector2d centre =
      0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  const double half_width = std::clamp(0.6 * cell_px, 1.0, 3.0);
  std::array<Eigen::Vector2d, 4> normals;
  std::array<std::vector<EdgeProfile>, 4> profiles;
  // Profiles that could not be read (off the image, no edge) or whose white
  // end is not the margin's, by edge, at their positions along it.
  std::array<std::vector<double>, 4> covered;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d a = corners[k], b = corners[(k + 1) % 4];
    Eigen::Vector2d n(b.y() - a.y(), a.x() - b.x());
    if (n.norm() < 1e-9) return fit;
    n.normalize();
    if (n.dot(0.5 * (a + b) - centre) < 0) n = -n;
    normals[k] = n;
    profiles[k] = SampleEdge(gray, a, b, n, half_width, &covered[k]);
  }
  // The margin is white paper all round the tag: a profile whose white end
  // reads darker than the tag's white (its upper quartile, which the
  // uncovered three quarters of the profiles set) lies under a hand, the
  // pen or a shadow, where the crossing is that of the border against the
  // occluder. It is left out.
  std::vector<double> whites;
  for (const auto& edge : profiles)
    for (const EdgeProfile& f : edge) whites.push_back(f.Bright());
  if (!whites.empty()) {
    const size_t q = whites.size() * 3 / 4;
    std::nth_element(whites.begin(), whites.begin() + q, whites.end());
    const double least_white = limits.margin_share * whites[q];
    for (int k = 0; k < 4; ++k) {
      // An occluder's own edge is blurred over a profile's spacing: the
      // profiles next to one it covers are partly covered and are left
      // out too.
      const double spacing =
          0.76 / SamplesAlongEdge((corners[(k + 1) % 4] - corners[k]).norm());
      std::vector<double> dark;
      for (const EdgeProfile& f : profiles[k])
        if (f.Bright() < least_white) dark.push_back(f.t);
      if (dark.empty()) continue;
      std::vector<EdgeProfile> kept;
      for (const EdgeProfile& f : profiles[k]) {
        const bool beside = std::any_of(
            dark.begin(), dark.end(),
            [&](double t) { return std::abs(t - f.t) < 1.5 * spacing; });
        if (beside) {
          covered[k].push_back(f.t);
        } else {
          kept.push_back(f);
        }
      }
      profiles[k].swap(kept);
    }
  }
  // Corner k ends edge k - 1 and starts edge k: covered profiles on the
  // halves of those edges next to it mean the occluder reaches towards it.
  std::array<bool, 4> covered_near;
  for (int k = 0; k < 4; ++k) {
    const int prev = (k + 3) % 4;
    covered_near[k] = std::any_of(covered[prev].begin(), covered[prev].end(),
                                  [](double t) { return t > 0.5; }) ||
                      std::any_of(covered[k].begin(), covered[k].end(),
                                  [](double t) { return t < 0.5; });
  }
  // Where the correction applies, by the cell's size in pixels. On cells
  // under ~3 px the reading point lies within ~1.5 px of the edge and of
  // the next cell, which a webcam's defocus mixes as well: there the reading
  // is no surer than a profile's own dark end and (shared by all four
  // edges) its noise becomes a distance jitter of a tiny face. On cells over
  // ~6 px the profile's dark end lies 3 px inside the edge and more than
  // 3 px from the next cell, where the lift is under 0.1% at the benchmark's
  // defocus, and what differs between the two readings is the real camera's
  // own processing (on the ViSP photo the correction moved the poses away
  // from ViSP's). It fades in from 2.4 to 3 px cells and out from 5 to 7 px
  // (tags of 19-24 and 40-56 px).
  const double weight = std::clamp((cell_px - 2.4) / 0.6, 0.0, 1.0) *
                        std::clamp((7.0 - cell_px) / 2.0, 0.0, 1.0);
  // Each profile's edge point: the crossing of the mid level between its
  // white end and `black_ratio` times it, or its own dark end when
  // black_ratio < 0.
  std::array<Line, 4> lines;
  std::array<bool, 4> ok;
  auto fit_lines = [&](double black_ratio) {
    for (int k = 0; k < 4; ++k) {
      std::vector<Eigen::Vector2d> points;
      for (const EdgeProfile& f : profiles[k]) {
        const double dark =
            black_ratio >= 0
                ? weight * black_ratio * f.Bright() + (1 - weight) * f.Dark()
                : f.Dark();
        double r = 0;
        if (f.Bright() - dark >= 10 &&
            Crossing(f, 0.5 * (dark + f.Bright()), &r))
          points.push_back(ToIdeal(lens, f.centre + r * normals[k]));
      }
      ok[k] = FitLine(std::move(points), &lines[k]);
    }
  };
  fit_lines(-1);
  // The black border is one cell wide: under blur, a white cell inside it
  // lifts the border's level where a profile reads its dark end, the mid
  // level rises and the crossing moves outward (by up to ~0.08 px on 25 px
  // tags, which puts a small tag ~0.6% too close). With the tag's cells
  // known, the border's own black is read on the fitted lines at the middle
  // of each border cell that has a black cell inside it (not the corner
  // cells, which the margin lightens from two sides), as a ratio to the
  // white at the same distance outside (the two inks' reflectances: the
  // ratio holds under shading across the tag, in linear light); then every
  // profile crosses the mid level between its own white and that share of
  // it. The cells read are fixed by the tag's code, so the estimate does
  // not switch with the noise from frame to frame. Each round moves the
  // profiles onto the lines the black was read on, so that the dark and
  // white ends sit at the same distances from the edge in both readings,
  // and refits; three rounds (on 20 mm tags blurred by 1.2 px the outward
  // bias falls +0.168 -> +0.095 -> +0.067 px from the local dark end to
  // one round to three).
  for (int round = 0; bitmap && weight > 0 && round < 3; ++round) {
    const std::optional<double> black_ratio = BorderBlackRatio(
        gray, *bitmap, corners, normals, lines, ok, half_width, lens);
    if (!black_ratio) break;
    for (int k = 0; k < 4; ++k) {
      if (!ok[k]) continue;
      std::vector<EdgeProfile> moved;
      for (const EdgeProfile& f : profiles[k]) {
        EdgeProfile m;
        const Eigen::Vector2d on_line =
            ToImage(lens, lines[k].Project(ToIdeal(lens, f.centre)));
        m.t = f.t;
        if (SampleProfile(gray, on_line, normals[k], half_width, &m))
          moved.push_back(m);
      }
      profiles[k].swap(moved);
    }
    // An edge the new levels cannot fit keeps its last line (a corner
    // falling back to libapriltag's would jump between frames).
    const std::array<Line, 4> last_lines = lines;
    const std::array<bool, 4> last_ok = ok;
    fit_lines(*black_ratio);
    for (int k = 0; k < 4; ++k) {
      if (!ok[k] && last_ok[k]) {
        lines[k] = last_lines[k];
        ok[k] = true;
      }
    }
  }
  for (int k = 0; k < 4; ++k) {
    const int prev = (k + 3) % 4;
    // Where an occluder covers the margin next to a corner, libapriltag's
    // outline follows the occluder: the corner is trusted only when both
    // its edges are fitted on uncovered profiles.
    fit.occluded[k] = covered_near[k];
    if (!ok[prev] || !ok[k]) continue;
    // point_prev + s dir_prev = point_k + u dir_k
    Eigen::Matrix2d m;
    m.col(0) = lines[prev].dir;
    m.col(1) = -lines[k].dir;
    if (std::abs(m.determinant()) < 1e-3) continue;
    const Eigen::Vector2d su =
        m.inverse() * (lines[k].point - lines[prev].point);
    const Eigen::Vector2d c =
        ToImage(lens, lines[prev].point + su(0) * lines[prev].dir);
    // Next to an occluder the lines are fitted on what is left of the two
    // edges and extrapolated to the corner: only from a fifth of each edge
    // or more (on less, a profile's noise tilts the line by more than the
    // corner may be off).
    const bool supported =
        std::min(Support(profiles[prev]), Support(profiles[k])) >= 0.2;
    if (covered_near[k] && !supported) continue;
    const double limit =
        covered_near[k] ? std::max(limits.max_shift_px,
                                   limits.max_occluded_shift_cells * cell_px)
                        : limits.max_shift_px;
    if ((c - corners[k]).norm() <= limit) {
      fit.corners[k] = c;
      fit.occluded[k] = false;
    }
  }
  return fit;
}

struct TagDetector::Impl {
  std::unique_ptr<TagFamily> family;
  apriltag_detector_t* detector = nullptr;
  cv::Mat gray;        // conversion buffer for colour input
  cv::Mat decode_lut;  // 8-bit value -> linear 8-bit; empty when linear
  cv::Mat linear;      // the decoded frame
  std::unordered_map<int, TagBitmap> bitmaps;  // by id, as detected
  std::optional<LensPixels> lens;  // a distorting lens (options.lens)

  ~Impl() {
    if (detector) apriltag_detector_destroy(detector);
  }
};

TagDetector::TagDetector(const TagDetectorOptions& options)
    : options_(options), impl_(new Impl) {
  std::string error;
  RIPPLE_CHECK(options.IsValid(&error),
               "TagDetector: invalid options: " + error);
  impl_->family = TagFamily::Create(options.family);
  if (options.transfer != geometry::Transfer::kLinear)
    impl_->decode_lut = DecodeToLinearLut(options.transfer);
  if (options.lens && options.lens->HasDistortion())
    impl_->lens.emplace(*options.lens);
  impl_->detector = apriltag_detector_create();
  apriltag_detector_add_family_bits(impl_->detector, impl_->family->get(),
                                    std::max(options.max_hamming, 1));
  apriltag_detector_t* td = impl_->detector;
  td->quad_decimate = static_cast<float>(options.quad_decimate);
  td->quad_sigma = static_cast<float>(options.quad_sigma);
  td->nthreads = options.threads;
  td->refine_edges = options.refine_edges;
  td->decode_sharpening = options.decode_sharpening;
  td->qtp.min_white_black_diff = options.min_white_black_diff;
  td->debug = false;
}

TagDetector::~TagDetector() = default;
TagDetector::TagDetector(TagDetector&&) noexcept = default;
TagDetector& TagDetector::operator=(TagDetector&&) noexcept = default;

std::vector<TagDetection> TagDetector::Detect(
    const cv::Mat& image, const std::vector<cv::Rect>& rois,
    std::optional<double> quad_decimate) {
  RIPPLE_CHECK(image.depth() == CV_8U, "TagDetector: image must be 8-bit");
  RIPPLE_CHECK(!quad_decimate || *quad_decimate >= 1.0,
               "TagDetector: quad_decimate must be >= 1");
  // The call's decimation, put back on every return.
  struct Decimation {
    apriltag_detector_t* td;
    float kept;
    ~Decimation() { td->quad_decimate = kept; }
  } decimation{impl_->detector, impl_->detector->quad_decimate};
  if (quad_decimate)
    impl_->detector->quad_decimate = static_cast<float>(*quad_decimate);
  const cv::Mat* gray = &image;
  if (image.channels() == 3) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGR2GRAY);
    gray = &impl_->gray;
  } else if (image.channels() == 4) {
    cv::cvtColor(image, impl_->gray, cv::COLOR_BGRA2GRAY);
    gray = &impl_->gray;
  }
  if (!impl_->decode_lut.empty()) {
    cv::LUT(*gray, impl_->decode_lut, impl_->linear);
    gray = &impl_->linear;
  }
  std::vector<cv::Rect> regions;
  const cv::Rect whole(0, 0, gray->cols, gray->rows);
  if (rois.empty()) {
    // libapriltag's quad search reads past the edges of images smaller than
    // a few pixels (it crashed on 1x1 and 4x3); no tag fits in them anyway.
    if (whole.width >= kMinImageSide && whole.height >= kMinImageSide)
      regions.push_back(whole);
  } else {
    for (const cv::Rect& r : rois) {
      const cv::Rect c = r & whole;
      if (c.width >= kMinImageSide && c.height >= kMinImageSide)
        regions.push_back(c);
    }
  }
  std::map<int, TagDetection> by_id;
  for (const cv::Rect& r : regions) {
    // A view into the frame: libapriltag reads rows with the parent stride.
    image_u8_t im{r.width, r.height, static_cast<int32_t>(gray->step[0]),
                  const_cast<uint8_t*>(gray->ptr<uint8_t>(r.y) + r.x)};
    zarray_t* found = apriltag_detector_detect(impl_->detector, &im);
    for (int i = 0; i < zarray_size(found); ++i) {
      apriltag_detection_t* det;
      zarray_get(found, i, &det);
      if (det->hamming > options_.max_hamming ||
          det->decision_margin < options_.min_decision_margin)
        continue;
      // libapriltag's p[] runs bottom-left, bottom-right, top-right,
      // top-left of the tag image (its tag frame has y down, p[0] at
      // (-1, +1)); ours is TL, TR, BR, BL.
      std::array<Eigen::Vector2d, 4> raw;
      for (int k = 0; k < 4; ++k) {
        raw[k] =
            Eigen::Vector2d(det->p[3 - k][0] + r.x, det->p[3 - k][1] + r.y);
      }
      TagDetection d;
      d.id = det->id;
      if (options_.edge_fit) {
        const auto shifted = CorrectCorners(raw, options_.pixel_offset_px, 0);
        double size = 0;
        for (int k = 0; k < 4; ++k)
          size += 0.25 * (shifted[(k + 1) % 4] - shifted[k]).norm();
        const double cell_px = size / impl_->family->width_at_border();
        const TagBitmap* bitmap = nullptr;
        if (options_.edge_fit_border_black) {
          auto it = impl_->bitmaps.find(d.id);
          if (it == impl_->bitmaps.end()) {
            std::optional<TagBitmap> b = MakeTagBitmap(*impl_->family, d.id);
            if (b) it = impl_->bitmaps.emplace(d.id, std::move(*b)).first;
          }
          if (it != impl_->bitmaps.end()) bitmap = &it->second;
        }
        const EdgeFit fit =
            FitTagEdges(*gray, shifted, cell_px, options_.edge_fit_limits,
                        bitmap, impl_->lens ? &*impl_->lens : nullptr);
        d.corners = CorrectCorners(fit.corners, 0.0, options_.edge_outward_px);
        d.corner_occluded = fit.occluded;
      } else {
        d.corners = CorrectCorners(raw, options_.pixel_offset_px,
                                   options_.edge_outward_px);
      }
      d.decision_margin = det->decision_margin;
      d.hamming = det->hamming;
      auto it = by_id.find(d.id);
      if (it == by_id.end() || it->second.decision_margin < d.decision_margin)
        by_id[d.id] = d;
    }
    apriltag_detections_destroy(found);
  }
  std::vector<TagDetection> out;
  out.reserve(by_id.size());
  for (auto& [id, d] : by_id) out.push_back(d);
  return out;
}

}  // namespace ripple::tracking
