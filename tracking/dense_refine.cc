#include "tracking/dense_refine.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "tracking/bilinear.h"

namespace ripple::tracking {

bool DenseRefineOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "dense refinement: " + what;
    return false;
  };
  if (samples_per_cell < 1 || samples_per_cell > 8)
    return fail("samples_per_cell must be in [1, 8]");
  if (!(min_template_gradient >= 0)) return fail("min_template_gradient < 0");
  if (!(min_facing_cos >= 0 && min_facing_cos < 1))
    return fail("min_facing_cos must be in [0, 1)");
  if (!(min_contrast_dn >= 0)) return fail("min_contrast_dn < 0");
  if (max_iterations < 1 || max_iterations > 50)
    return fail("max_iterations must be in [1, 50]");
  if (coarse_iterations < 0 || coarse_iterations >= max_iterations)
    return fail("coarse_iterations must be in [0, max_iterations)");
  if (!(huber_dn > 0)) return fail("huber_dn must be positive");
  if (!(outlier_spreads >= 0 && outlier_min_dn >= 0))
    return fail("outlier_spreads and outlier_min_dn must be non-negative");
  if (!(max_rotation_deg > 0 && max_translation_m > 0))
    return fail("max_rotation_deg and max_translation_m must be positive");
  return true;
}

namespace {

// Share of a unit cell [a, a + 1] under a Gaussian of sigma `s` centred at x.
double CellWeight(double x, double a, double s) {
  const double k = 1.0 / (s * std::sqrt(2.0));
  return 0.5 * (std::erf((a + 1 - x) * k) - std::erf((a - x) * k));
}

// The bitmap (0 black, 1 white; white outside) blurred by a Gaussian of
// sigma `s` cells, at bitmap coordinates (u right, v down, cells).
double BlurredBitmap(const TagBitmap& b, double u, double v, double s) {
  const int reach = static_cast<int>(std::ceil(4 * s)) + 1;
  const int c0 = static_cast<int>(std::floor(u)) - reach;
  const int r0 = static_cast<int>(std::floor(v)) - reach;
  double sum = 0, total = 0;
  for (int r = r0; r <= r0 + 2 * reach; ++r) {
    const double wr = CellWeight(v, r, s);
    for (int c = c0; c <= c0 + 2 * reach; ++c) {
      const double w = wr * CellWeight(u, c, s);
      const bool inside =
          r >= 0 && c >= 0 && r < b.total_width && c < b.total_width;
      sum += w * (inside && b.black(r, c) ? 0.0 : 1.0);
      total += w;
    }
  }
  return total > 0 ? sum / total : 1.0;
}

// Second derivatives (uu, uv, vv) of BlurredBitmap at (u, v), in closed
// form: each cell's weight is a product of two erf differences, whose
// derivatives are Gaussians.
std::array<double, 3> BlurredBitmapCurvature(const TagBitmap& b, double u,
                                             double v, double s) {
  const int reach = static_cast<int>(std::ceil(4 * s)) + 1;
  const int c0 = static_cast<int>(std::floor(u)) - reach;
  const int r0 = static_cast<int>(std::floor(v)) - reach;
  const int n = 2 * reach + 1;
  const double k = 1.0 / (s * std::sqrt(2.0));
  const double norm = k / std::sqrt(M_PI);
  // Weight of the cell [a, a + 1] at x and its first two derivatives in x.
  auto weights = [&](double x, double a, double* w, double* d1, double* d2) {
    const double p = (a - x) * k, q = (a + 1 - x) * k;
    const double ep = std::exp(-p * p), eq = std::exp(-q * q);
    *w = 0.5 * (std::erf(q) - std::erf(p));
    *d1 = norm * (ep - eq);
    *d2 = norm * 2 * k * (p * ep - q * eq);
  };
  std::vector<double> wr(n), dr(n), ddr(n), wc(n), dc(n), ddc(n);
  for (int i = 0; i < n; ++i) {
    weights(v, r0 + i, &wr[i], &dr[i], &ddr[i]);
    weights(u, c0 + i, &wc[i], &dc[i], &ddc[i]);
  }
  std::array<double, 3> h{0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const int r = r0 + i;
    for (int j = 0; j < n; ++j) {
      const int c = c0 + j;
      const bool inside =
          r >= 0 && c >= 0 && r < b.total_width && c < b.total_width;
      if (inside && b.black(r, c)) continue;  // black adds 0
      h[0] += wr[i] * ddc[j];
      h[1] += dr[i] * dc[j];
      h[2] += ddr[i] * wc[j];
    }
  }
  return h;
}

// Bilinear sample with the image gradient at (x, y): central differences
// over +-1 pixel, themselves bilinear. The caller keeps (x, y) at least 1.5
// pixels inside the image.
inline void BilinearWithGradient(const cv::Mat& g, double x, double y,
                                 double* v, Eigen::RowVector2d* grad) {
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const size_t step = g.step[0];
  // Rows y0 - 1 .. y0 + 2, columns x0 - 1 .. x0 + 2.
  const uint8_t* p = g.ptr<uint8_t>(y0 - 1) + (x0 - 1);
  double m[4][4];
  for (int r = 0; r < 4; ++r, p += step)
    for (int c = 0; c < 4; ++c) m[r][c] = p[c];
  auto at = [&](int r, int c) {  // bilinear at (x0 + c - 1 + fx, ...)
    return (1 - fy) * ((1 - fx) * m[r][c] + fx * m[r][c + 1]) +
           fy * ((1 - fx) * m[r + 1][c] + fx * m[r + 1][c + 1]);
  };
  *v = at(1, 1);
  // I(x + 1) - I(x - 1) from the 4x4 neighbourhood: columns shift by one.
  const double gx =
      (1 - fy) * ((1 - fx) * (m[1][2] - m[1][0]) + fx * (m[1][3] - m[1][1])) +
      fy * ((1 - fx) * (m[2][2] - m[2][0]) + fx * (m[2][3] - m[2][1]));
  const double gy =
      (1 - fx) * ((1 - fy) * (m[2][1] - m[0][1]) + fy * (m[3][1] - m[1][1])) +
      fx * ((1 - fy) * (m[2][2] - m[0][2]) + fy * (m[3][2] - m[1][2]));
  *grad = Eigen::RowVector2d(0.5 * gx, 0.5 * gy);
}

// One linearised sample: template value, image value, and the derivative of
// the image value with respect to the pose increment (rotation, translation
// in the camera frame).
struct Row {
  int face = 0;
  const DenseTagModel::Sample* sample = nullptr;
  double t = 0, i = 0;
  Eigen::Matrix<double, 1, 6> j = Eigen::Matrix<double, 1, 6>::Zero();
};

// A face's template blur as a continuous level: `level` in [0, kBlurLevels
// - 1] blends the two precomputed levels around it linearly, so that the
// template's blur follows the image's without jumping from one level to the
// next (a jump changes the fitted scale of a small face: its distance).
// Level -1 takes every sample and leaves the template value at level 0.
struct BlurLevel {
  int lo = 0, hi = 0;   // precomputed levels blended
  double w = 0;         // weight of `hi`
  unsigned mask = ~0u;  // samples informative at `lo` or `hi`
};

BlurLevel MakeBlurLevel(double level) {
  BlurLevel b;
  if (level < 0) return b;
  constexpr int kTop = DenseTagModel::kBlurLevels - 1;
  b.lo = std::min(static_cast<int>(level), kTop);
  b.hi = std::min(b.lo + 1, kTop);
  b.w = b.hi == b.lo ? 0.0 : level - b.lo;
  b.mask = (1u << b.lo) | (b.w > 0 ? 1u << b.hi : 0u);
  return b;
}

// The part of a face's blur that is not round, in the tag plane (cells
// squared): D = Sigma - (tr Sigma / 2) I with Sigma the image's round blur
// pulled back onto the face, scaled so that its round part is the level's
// own blur. Stored as (D_uu, D_uv, D_vv); zero for a frontal face.
using BlurShape = Eigen::Vector3d;

double LevelSigmaCells(const BlurLevel& b) {
  return (1 - b.w) * DenseTagModel::kBlurCells[b.lo] +
         b.w * DenseTagModel::kBlurCells[b.hi];
}

// D for a round part of one cell squared: 2 M / tr M - I, where M = A^-1
// A^-T is a round blur of one pixel squared seen in the tag plane through
// the face's local affine map A (pixels per cell along u and v).
BlurShape UnitBlurShape(const Camera& camera, const DenseTagModel::Face& face,
                        const Pose& pose) {
  const Eigen::Vector3d c = pose * face.centre;
  if (c.z() < 1e-3) return BlurShape::Zero();
  Eigen::Matrix<double, 2, 3> dpix;
  camera.ProjectWithJacobian(c, &dpix);
  Eigen::Matrix2d a;
  a.col(0) = dpix * (pose.R() * face.cell_u);
  a.col(1) = dpix * (pose.R() * face.cell_v);
  if (!(std::abs(a.determinant()) > 1e-12)) return BlurShape::Zero();
  const Eigen::Matrix2d a_inv = a.inverse();
  const Eigen::Matrix2d m = a_inv * a_inv.transpose();
  const Eigen::Matrix2d d = m / (0.5 * m.trace()) - Eigen::Matrix2d::Identity();
  return BlurShape(d(0, 0), d(0, 1), d(1, 1));
}

BlurShape FaceBlurShape(const Camera& camera, const DenseTagModel::Face& face,
                        const Pose& pose, const BlurLevel& b) {
  return std::pow(LevelSigmaCells(b), 2) * UnitBlurShape(camera, face, pose);
}

// The template value at a sample: the level's round template, corrected by
// the blur's non-round part D to first order. Gaussian blur follows the heat
// equation, dT/dSigma_ij = 1/2 d2T/dx_i dx_j, so T(Sigma + D) ~ T(Sigma) +
// 1/2 (D_uu T_uu + 2 D_uv T_uv + D_vv T_vv).
double TemplateValue(const DenseTagModel::Sample& s, const BlurLevel& b,
                     const BlurShape& d = BlurShape::Zero()) {
  double t = (1 - b.w) * s.value[b.lo] + b.w * s.value[b.hi];
  if (d.isZero()) return t;
  for (int k = 0; k < 2; ++k) {
    const int l = k == 0 ? b.lo : b.hi;
    const double w = k == 0 ? 1 - b.w : b.w;
    if (w == 0) continue;
    const auto& c = s.curvature[l];
    t += w * 0.5 * (d(0) * c[0] + 2 * d(1) * c[1] + d(2) * c[2]);
  }
  return t;
}

// Samples every face of `faces` at `pose`: the image value of each sample
// inside the image and, with `jacobian`, its derivative with respect to the
// pose increment.
void Linearise(const cv::Mat& gray, const Camera& camera,
               const DenseTagModel& model, const std::vector<int>& faces,
               const std::vector<double>& levels, const Pose& pose,
               bool jacobian, bool anisotropic, std::vector<Row>* rows) {
  rows->clear();
  const Eigen::Matrix3d r = pose.R();
  // The gradient's taps (+-1 px) must be inside the image too.
  const double x_max = gray.cols - 3, y_max = gray.rows - 3;
  for (size_t f = 0; f < faces.size(); ++f) {
    const BlurLevel blur = MakeBlurLevel(levels[f]);
    const DenseTagModel::Face& face = model.faces()[faces[f]];
    const BlurShape shape = anisotropic && levels[f] >= 0
                                ? FaceBlurShape(camera, face, pose, blur)
                                : BlurShape::Zero();
    for (const DenseTagModel::Sample& s : face.samples) {
      if (!(s.informative & blur.mask)) continue;
      const Eigen::Vector3d p = r * s.point + pose.translation;
      if (p.z() < 1e-3) continue;
      Row row;
      row.face = static_cast<int>(f);
      row.sample = &s;
      row.t = TemplateValue(s, blur, shape);
      if (!jacobian) {
        const Eigen::Vector2d uv = camera.Project(p);
        if (!(uv.x() >= 1 && uv.y() >= 1 && uv.x() < x_max && uv.y() < y_max))
          continue;
        SampleBilinear(gray, uv.x(), uv.y(), &row.i);
        rows->push_back(row);
        continue;
      }
      Eigen::Matrix<double, 2, 3> dpix;
      const Eigen::Vector2d uv = camera.ProjectWithJacobian(p, &dpix);
      if (!(uv.x() >= 1 && uv.y() >= 1 && uv.x() < x_max && uv.y() < y_max))
        continue;
      double i;
      Eigen::RowVector2d grad;
      BilinearWithGradient(gray, uv.x(), uv.y(), &i, &grad);
      // p' = exp(w) p + v, so dI/dv = g and dI/dw = g (w x p) / dw = p x g
      // with g = dI/dp.
      const Eigen::Vector3d g = (grad * dpix).transpose();
      row.i = i;
      row.j << p.cross(g).transpose(), g.transpose();
      rows->push_back(row);
    }
  }
}

struct Fit {
  std::vector<double> gain, offset;
  std::vector<bool> usable;
};

// Sums for the least-squares line image = gain * template + offset.
struct LineSums {
  double n = 0, t = 0, tt = 0, i = 0, ti = 0, ii = 0;
  void Add(double tv, double iv) {
    n += 1;
    t += tv;
    tt += tv * tv;
    i += iv;
    ti += tv * iv;
    ii += iv * iv;
  }
  // False when the template does not vary.
  bool Solve(double* gain, double* offset) const {
    const double det = n * tt - t * t;
    if (!(n >= 3 && det > 1e-9 * n * n)) return false;
    *gain = (n * ti - t * i) / det;
    *offset = (i - *gain * t) / n;
    return true;
  }
  // Sum of squared residuals of the solved line.
  double Residual(double gain, double offset) const {
    return ii - gain * ti - offset * i;
  }
};

// Per-face gain and offset (image = gain * template + offset) by least
// squares: over all rows, then, with a finite `clip`, twice more over the
// rows within `clip` grey levels of the last line (an occluder's samples
// then do not set the face's contrast). A face is usable when its gain (the
// black-to-white contrast) is at least `min_contrast`.
Fit FitGains(const std::vector<Row>& rows, int num_faces, double min_contrast,
             double clip = std::numeric_limits<double>::infinity()) {
  Fit fit;
  fit.gain.assign(num_faces, 0);
  fit.offset.assign(num_faces, 0);
  fit.usable.assign(num_faces, false);
  std::vector<bool> solved(num_faces, false);
  const int rounds = std::isfinite(clip) ? 3 : 1;
  for (int round = 0; round < rounds; ++round) {
    std::vector<LineSums> sums(num_faces);
    for (const Row& r : rows) {
      if (round > 0 && solved[r.face] &&
          std::abs(r.i - (fit.gain[r.face] * r.t + fit.offset[r.face])) > clip)
        continue;
      sums[r.face].Add(r.t, r.i);
    }
    for (int f = 0; f < num_faces; ++f) {
      double gain, offset;
      if (!sums[f].Solve(&gain, &offset)) continue;
      fit.gain[f] = gain;
      fit.offset[f] = offset;
      solved[f] = true;
    }
  }
  for (int f = 0; f < num_faces; ++f)
    fit.usable[f] = solved[f] && fit.gain[f] >= min_contrast;
  return fit;
}

double HuberCost(double r, double k) {
  const double a = std::abs(r);
  return a <= k ? 0.5 * r * r : k * (a - 0.5 * k);
}

// Robust cost of the rows of usable faces (`n` of them): Huber's loss,
// constant beyond `clip` (a residual that large is an occluder, not a
// misalignment); and the RMS of the residuals within `clip`.
void Cost(const std::vector<Row>& rows, const Fit& fit, double huber,
          double clip, double* cost, double* rms, int* n) {
  *cost = 0;
  double sq = 0;
  int inliers = 0;
  *n = 0;
  for (const Row& r : rows) {
    if (!fit.usable[r.face]) continue;
    const double e = r.i - (fit.gain[r.face] * r.t + fit.offset[r.face]);
    *cost += HuberCost(std::min(std::abs(e), clip), huber);
    ++*n;
    if (std::abs(e) <= clip) {
      sq += e * e;
      ++inliers;
    }
  }
  *rms = inliers > 0 ? std::sqrt(sq / inliers) : 0;
}

// Template blur of the coarse phase (an index into kBlurCells).
constexpr double kCoarseLevel = 2;

// Steps of the search for a face's continuous blur level.
constexpr int kLevelSteps = 16;  // per precomputed level

Pose Apply(const Pose& pose, const Eigen::Matrix<double, 6, 1>& d) {
  const Eigen::Vector3d w = d.head<3>();
  const double angle = w.norm();
  const Eigen::Quaterniond q =
      angle > 1e-15 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle))
                    : Eigen::Quaterniond::Identity();
  Pose out;
  out.rotation = (q * pose.rotation).normalized();
  out.translation = q * pose.translation + d.tail<3>();
  return out;
}

}  // namespace

std::optional<DenseTagModel> DenseTagModel::Create(
    const TagFamily& family, const std::vector<TagPlacement>& tags,
    const DenseRefineOptions& options, std::string* error) {
  DenseTagModel model;
  for (const TagPlacement& tag : tags) {
    const std::optional<TagBitmap> bitmap = MakeTagBitmap(family, tag.id);
    if (!bitmap) {
      if (error)
        *error = "tag id " + std::to_string(tag.id) + " is not in family " +
                 family.name();
      return std::nullopt;
    }
    Face face;
    face.id = tag.id;
    face.centre = tag.object_from_tag.translation;
    face.normal = -(tag.object_from_tag.R().col(2));  // tag z points inward
    const int total = bitmap->total_width;
    const double border = 0.5 * (total - bitmap->width_at_border);
    const double cell_m = tag.edge_m / bitmap->width_at_border;
    face.cell_u = cell_m * tag.object_from_tag.R().col(0);
    face.cell_v = cell_m * tag.object_from_tag.R().col(1);
    const int n = options.samples_per_cell;
    const double h = 0.05;  // cells, for the template gradient
    // Samples over the bitmap less the outer half cell (beyond it lies the
    // cube's edge or the board around the tag, which the model does not
    // know).
    for (int j = 0; j < total * n; ++j) {
      for (int i = 0; i < total * n; ++i) {
        const double u = (i + 0.5) / n, v = (j + 0.5) / n;
        if (u < 0.5 || v < 0.5 || u > total - 0.5 || v > total - 0.5) continue;
        Sample sample;
        for (int l = 0; l < kBlurLevels; ++l) {
          const double sl = kBlurCells[l];
          const double gx = (BlurredBitmap(*bitmap, u + h, v, sl) -
                             BlurredBitmap(*bitmap, u - h, v, sl)) /
                            (2 * h);
          const double gy = (BlurredBitmap(*bitmap, u, v + h, sl) -
                             BlurredBitmap(*bitmap, u, v - h, sl)) /
                            (2 * h);
          if (std::hypot(gx, gy) >= options.min_template_gradient)
            sample.informative |= 1u << l;
          sample.value[l] =
              static_cast<float>(BlurredBitmap(*bitmap, u, v, sl));
          const std::array<double, 3> c =
              BlurredBitmapCurvature(*bitmap, u, v, sl);
          sample.curvature[l] = {static_cast<float>(c[0]),
                                 static_cast<float>(c[1]),
                                 static_cast<float>(c[2])};
        }
        if (sample.informative == 0) continue;
        const Eigen::Vector3d in_tag((u - border) * cell_m - 0.5 * tag.edge_m,
                                     (v - border) * cell_m - 0.5 * tag.edge_m,
                                     0.0);
        sample.point = tag.object_from_tag * in_tag;
        face.samples.push_back(sample);
      }
    }
    model.faces_.push_back(std::move(face));
  }
  return model;
}

bool DenseRefinePose(const cv::Mat& gray, const Camera& camera,
                     const DenseTagModel& model,
                     const DenseRefineOptions& options, Pose* cam_from_object,
                     DenseRefineResult* result) {
  DenseRefineResult local;
  DenseRefineResult& res = result ? *result : local;
  res = DenseRefineResult{};
  if (gray.empty() || gray.type() != CV_8UC1) return false;
  const Pose start = *cam_from_object;
  // Faces turned towards the camera at the starting pose.
  std::vector<int> faces;
  const Eigen::Matrix3d r0 = start.R();
  for (size_t f = 0; f < model.faces().size(); ++f) {
    const DenseTagModel::Face& face = model.faces()[f];
    const Eigen::Vector3d c = start * face.centre;
    const Eigen::Vector3d n = r0 * face.normal;
    if (c.z() <= 0 || -n.dot(c.normalized()) < options.min_facing_cos) continue;
    faces.push_back(static_cast<int>(f));
  }
  if (faces.empty()) return false;
  const int nf = static_cast<int>(faces.size());

  // Per face, the template blur that fits the image best at the start: the
  // continuous level whose blended template leaves the least squared
  // residual after the face's gain and offset, searched in steps of
  // 1 / kLevelSteps.
  std::vector<double> levels(nf, 0);
  std::vector<Row> rows;
  // Each face's non-round blur at the start, per cell squared of round blur:
  // every level's template is blurred as the image is.
  std::vector<BlurShape> unit(nf, BlurShape::Zero());
  if (options.anisotropic_blur) {
    for (int f = 0; f < nf; ++f)
      unit[f] = UnitBlurShape(camera, model.faces()[faces[f]], start);
  }
  {
    // Every sample (level -1), values only.
    Linearise(gray, camera, model, faces, std::vector<double>(nf, -1), start,
              false, false, &rows);
    // One pass: per face the moments of the image and the five templates,
    // from which the line fit of any blend follows.
    constexpr int kL = DenseTagModel::kBlurLevels;
    using Vec = Eigen::Matrix<double, kL, 1>;
    struct Moments {
      double n = 0, i = 0, ii = 0;
      Vec v = Vec::Zero(), vi = Vec::Zero();
      Eigen::Matrix<double, kL, kL> vv = Eigen::Matrix<double, kL, kL>::Zero();
    };
    std::vector<Moments> moments(nf);
    for (const Row& r : rows) {
      Moments& m = moments[r.face];
      Vec v =
          Eigen::Map<const Eigen::Matrix<float, kL, 1>>(r.sample->value.data())
              .cast<double>();
      const BlurShape& u = unit[r.face];
      if (!u.isZero()) {
        for (int l = 0; l < kL; ++l) {
          const auto& c = r.sample->curvature[l];
          const double s2 =
              DenseTagModel::kBlurCells[l] * DenseTagModel::kBlurCells[l];
          v(l) += 0.5 * s2 * (u(0) * c[0] + 2 * u(1) * c[1] + u(2) * c[2]);
        }
      }
      m.n += 1;
      m.i += r.i;
      m.ii += r.i * r.i;
      m.v += v;
      m.vi += r.i * v;
      m.vv.selfadjointView<Eigen::Upper>().rankUpdate(v);
    }
    for (int f = 0; f < nf; ++f) {
      const Moments& m = moments[f];
      const Eigen::Matrix<double, kL, kL> vv =
          m.vv.selfadjointView<Eigen::Upper>();
      double best = std::numeric_limits<double>::infinity();
      for (int k = 0; k <= (kL - 1) * kLevelSteps; ++k) {
        const double level = static_cast<double>(k) / kLevelSteps;
        const BlurLevel b = MakeBlurLevel(level);
        Vec c = Vec::Zero();
        c(b.lo) += 1 - b.w;
        c(b.hi) += b.w;
        LineSums sums;
        sums.n = m.n;
        sums.t = c.dot(m.v);
        sums.tt = c.dot(vv * c);
        sums.i = m.i;
        sums.ti = c.dot(m.vi);
        sums.ii = m.ii;
        double gain, offset;
        if (!sums.Solve(&gain, &offset)) continue;
        const double sse = sums.Residual(gain, offset);
        if (sse < best) {
          best = sse;
          levels[f] = level;
        }
      }
    }
  }
  // The starting cost on the chosen templates: the samples informative at
  // each face's level, out of those just taken.
  std::vector<BlurLevel> blur(nf);
  for (int f = 0; f < nf; ++f) blur[f] = MakeBlurLevel(levels[f]);
  rows.erase(
      std::remove_if(rows.begin(), rows.end(),
                     [&](const Row& r) {
                       return !(r.sample->informative & blur[r.face].mask);
                     }),
      rows.end());
  std::vector<BlurShape> shapes(nf);
  for (int f = 0; f < nf; ++f)
    shapes[f] = std::pow(LevelSigmaCells(blur[f]), 2) * unit[f];
  for (Row& r : rows)
    r.t = TemplateValue(*r.sample, blur[r.face], shapes[r.face]);
  Fit fit = FitGains(rows, nf, options.min_contrast_dn);
  // Residuals beyond `clip` are taken as occluded: a robust spread of the
  // start's residuals (1.4826 times their median absolute value), scaled.
  double clip = std::numeric_limits<double>::infinity();
  if (options.outlier_spreads > 0) {
    std::vector<double> abs_res;
    abs_res.reserve(rows.size());
    for (const Row& r : rows) {
      if (fit.usable[r.face])
        abs_res.push_back(
            std::abs(r.i - (fit.gain[r.face] * r.t + fit.offset[r.face])));
    }
    if (!abs_res.empty()) {
      auto mid = abs_res.begin() + abs_res.size() / 2;
      std::nth_element(abs_res.begin(), mid, abs_res.end());
      clip = std::max(options.outlier_spreads * 1.4826 * *mid,
                      options.outlier_min_dn);
      fit = FitGains(rows, nf, options.min_contrast_dn, clip);
    }
  }
  double cost0, rms0;
  int n0;
  Cost(rows, fit, options.huber_dn, clip, &cost0, &rms0, &n0);
  if (n0 < 12) return false;
  res.rms_before_dn = rms0;
  // The usable faces are fixed by the starting pose so that costs compare.
  const std::vector<bool> usable = fit.usable;

  Pose pose = start;
  double cost = cost0, rms = rms0;
  int n = n0;
  // Coarse to fine: the first iterations use a template at least
  // kCoarseLevel blurred, whose basin is wider than a sharp one's.
  std::vector<double> current = levels;
  for (double& l : current) l = std::max(l, kCoarseLevel);
  // Switches templates (and with them the informative samples) at `pose`.
  auto use_levels = [&](const std::vector<double>& lv, bool jacobian) {
    current = lv;
    Linearise(gray, camera, model, faces, lv, pose, jacobian,
              options.anisotropic_blur, &rows);
    fit = FitGains(rows, nf, 0.0, clip);
    for (int f = 0; f < nf; ++f) fit.usable[f] = fit.usable[f] && usable[f];
    Cost(rows, fit, options.huber_dn, clip, &cost, &rms, &n);
  };
  if (options.coarse_iterations > 0 && current != levels) {
    use_levels(current, true);
  } else {
    use_levels(levels, true);
  }
  std::vector<Row> trial_rows;
  trial_rows.reserve(rows.capacity());
  // J^T W J of the last step on the fine templates (of the last coarse one
  // if no fine step ran), in Apply's parameters.
  Eigen::Matrix<double, 6, 6> fine_hessian =
      Eigen::Matrix<double, 6, 6>::Zero();
  bool fine_seen = false;
  for (int it = 0; it < options.max_iterations; ++it) {
    if (it == options.coarse_iterations && current != levels)
      use_levels(levels, true);
    const bool coarse = current != levels;
    // Huber weights and the Gauss-Newton step on the usable faces.
    Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (const Row& r : rows) {
      if (!usable[r.face] || !fit.usable[r.face]) continue;
      const double e = r.i - (fit.gain[r.face] * r.t + fit.offset[r.face]);
      // Huber's weight; none beyond the clip (an occluded sample).
      const double abs_e = std::abs(e);
      if (abs_e > clip) continue;
      const double w =
          abs_e <= options.huber_dn ? 1.0 : options.huber_dn / abs_e;
      // Upper triangle only; mirrored below.
      for (int a = 0; a < 6; ++a) {
        const double wa = w * r.j(a);
        g(a) += wa * e;
        for (int b = a; b < 6; ++b) hessian(a, b) += wa * r.j(b);
      }
    }
    hessian.triangularView<Eigen::StrictlyLower>() = hessian.transpose();
    if (!coarse || !fine_seen) fine_hessian = hessian;
    fine_seen = fine_seen || !coarse;
    // A little damping keeps a weakly constrained direction from running off.
    hessian.diagonal() += 1e-6 * hessian.diagonal().cwiseAbs().maxCoeff() *
                          Eigen::Matrix<double, 6, 1>::Ones();
    const Eigen::Matrix<double, 6, 1> step = -hessian.ldlt().solve(g);
    if (!step.allFinite()) break;
    // Halve the step until the cost drops.
    bool improved = false;
    double scale = 1.0;
    for (int tries = 0; tries < 4; ++tries, scale *= 0.5) {
      const Pose trial = Apply(pose, scale * step);
      Linearise(gray, camera, model, faces, current, trial, false,
                options.anisotropic_blur, &trial_rows);
      Fit trial_fit = FitGains(trial_rows, nf, 0.0, clip);
      for (int f = 0; f < nf; ++f)
        trial_fit.usable[f] = trial_fit.usable[f] && usable[f];
      double c, q;
      int m;
      Cost(trial_rows, trial_fit, options.huber_dn, clip, &c, &q, &m);
      if (m >= n * 0.9 && c / std::max(m, 1) < cost / std::max(n, 1)) {
        pose = trial;
        fit = trial_fit;
        cost = c;
        rms = q;
        n = m;
        improved = true;
        break;
      }
    }
    res.iterations = it + 1;
    // Converged: a step under 0.005 degrees and 5 micrometres (0.01 mm at a
    // tip 0.14 m away).
    const bool converged = improved && scale * step.head<3>().norm() < 1e-4 &&
                           scale * step.tail<3>().norm() < 5e-6;
    if (!improved || converged) {
      if (!coarse) break;
      // On to the fine phase at once.
      it = std::max(it, options.coarse_iterations - 1);
      if (it + 1 >= options.max_iterations) break;
    }
    // Linearise at the new pose for the next iteration, unless that one
    // switches templates (use_levels does it then).
    const bool switching =
        it + 1 == options.coarse_iterations && current != levels;
    if (improved && it + 1 < options.max_iterations && !switching)
      Linearise(gray, camera, model, faces, current, pose, true,
                options.anisotropic_blur, &rows);
  }
  // The final cost must be on the fine templates to compare with the start.
  if (current != levels) use_levels(levels, false);
  res.faces = 0;
  for (int f = 0; f < nf; ++f) {
    res.faces += usable[f];
    if (usable[f]) res.blur_levels.push_back(levels[f]);
  }
  res.samples = n;
  res.rms_after_dn = rms;
  const double turn = RotationDistance(pose, start) * 180.0 / M_PI;
  const double move = (pose.translation - start.translation).norm();
  if (!(cost / std::max(n, 1) < cost0 / std::max(n0, 1)) ||
      turn > options.max_rotation_deg || move > options.max_translation_m)
    return false;
  *cam_from_object = pose;
  res.refined = true;
  // Apply's step (omega, v_a) moves the translation to exp(omega) t + v_a,
  // which is t + v with v = v_a - [t]x omega to first order: information
  // in (omega, v) is A^-T H A^-1 with A^-1 = [I 0; [t]x I].
  Eigen::Matrix<double, 6, 6> a_inv = Eigen::Matrix<double, 6, 6>::Identity();
  const Eigen::Vector3d& t = pose.translation;
  a_inv.block<3, 3>(3, 0) << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(),
      0;
  // The residual's RMS (grey levels; at least one, the 8-bit step) stands
  // for the noise: it holds the template's misfit too.
  const double sigma2 = std::max(rms * rms, 1.0);
  res.information = a_inv.transpose() * fine_hessian * a_inv / sigma2;
  return true;
}

}  // namespace ripple::tracking
