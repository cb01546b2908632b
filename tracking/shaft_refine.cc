#include "tracking/shaft_refine.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>

#include "geometry/polygon2d.h"
#include "tracking/bilinear.h"

namespace ripple::tracking {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The pose moved by delta = (omega, v): R' = exp(omega) R, t' = t + v.
Pose Perturbed(const Pose& p, const Vec6& delta) {
  const Eigen::Vector3d w = delta.head<3>();
  const double angle = w.norm();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  if (angle > 1e-15) q = Eigen::AngleAxisd(angle, w / angle);
  return Pose((q * p.rotation).normalized(), p.translation + delta.tail<3>());
}

// delta with Perturbed(from, delta) == to.
Vec6 Difference(const Pose& from, const Pose& to) {
  const Eigen::AngleAxisd aa(to.rotation * from.rotation.conjugate());
  Vec6 d;
  d.head<3>() = aa.angle() * aa.axis();
  d.tail<3>() = to.translation - from.translation;
  return d;
}

// The pose's information from the detected corners: sum of J^T J over the
// corners' pixel residuals, in delta's parameters.
Mat6 CornerInformation(const Camera& camera,
                       const std::vector<TagObservation>& corners,
                       const Pose& cam_from_pen) {
  Mat6 h = Mat6::Zero();
  const Eigen::Matrix3d r = cam_from_pen.R();
  for (const TagObservation& o : corners) {
    for (const Eigen::Vector3d& x : o.corners_in_object) {
      const Eigen::Vector3d y = r * x;
      const Eigen::Vector3d p = y + cam_from_pen.translation;
      if (p.z() <= 1e-6) continue;
      Eigen::Matrix<double, 2, 3> jp;
      camera.ProjectWithJacobian(p, &jp);
      Eigen::Matrix<double, 3, 6> dp;
      dp << -Skew(y), Eigen::Matrix3d::Identity();
      const Eigen::Matrix<double, 2, 6> j = jp * dp;
      h += j.transpose() * j;
    }
  }
  return h;
}

// The shaft's axis in the camera frame: its point at the tip and its unit
// direction towards the cube.
struct Axis {
  Eigen::Vector3d tip, dir;
};

Axis AxisInCamera(const PenSpec& pen, const Pose& cam_from_pen) {
  return {cam_from_pen * pen.tip_in_pen,
          cam_from_pen.R() * (-pen.tip_in_pen).normalized()};
}

// The silhouette point of the shaft at axis parameter s (metres from the
// tip) on side `side` (+1, -1), with the outward image normal there.
// False when the camera is inside the cylinder or behind the point.
bool ContourPoint(const Camera& camera, const Axis& axis, double radius,
                  double s, int side, Eigen::Vector2d* pixel,
                  Eigen::Vector2d* outward, double* depth) {
  // In the plane across the axis the camera centre sees the circle of the
  // shaft's section from its distance D; the tangent points lie at
  // -(r/D) q + side sqrt(1 - r^2/D^2) n, with q towards the axis and n
  // across both.
  const Eigen::Vector3d q3 =
      axis.tip - axis.tip.dot(axis.dir) * axis.dir;  // closest axis point
  const double d = q3.norm();
  if (d <= radius * 1.01) return false;
  const Eigen::Vector3d q = q3 / d;
  const Eigen::Vector3d n = axis.dir.cross(q);
  const double c = radius / d;
  const Eigen::Vector3d m = -c * q + side * std::sqrt(1 - c * c) * n;
  const Eigen::Vector3d centre = axis.tip + s * axis.dir;
  const Eigen::Vector3d p = centre + radius * m;
  const Eigen::Vector3d p_along = p + 0.001 * axis.dir;
  if (p.z() <= 1e-3 || p_along.z() <= 1e-3 || centre.z() <= 1e-3) return false;
  *pixel = camera.Project(p);
  const Eigen::Vector2d along = camera.Project(p_along) - *pixel;
  if (along.norm() < 1e-9) return false;
  Eigen::Vector2d u(-along.y(), along.x());
  u.normalize();
  if (u.dot(*pixel - camera.Project(centre)) < 0) u = -u;
  *outward = u;
  *depth = p.z();
  return true;
}

// Signed distance (metres) at which the ray through normalised point `ray`
// passes the axis, less the radius: 0 for a ray tangent to the shaft.
double Tangency(const Axis& axis, double radius, const Eigen::Vector3d& ray) {
  const Eigen::Vector3d m = ray.cross(axis.dir);
  const double mn = m.norm();
  if (mn < 1e-12) return -radius;
  return std::abs(axis.tip.dot(m)) / mn - radius;
}

struct Edge {
  Eigen::Vector3d ray;  // undistorted, z = 1
  double s = 0;         // axis parameter it was searched at
  double scale = 0;     // pixels per metre across the line of sight there
};

// Searches both sides' edges at the pose for a shaft of `radius`; false
// when a side has too few.
bool FindEdges(const cv::Mat& gray, const Camera& camera, const PenSpec& pen,
               const ShaftRefineOptions& o, const Pose& cam_from_pen,
               double radius, double search_px,
               std::array<std::vector<Edge>, 2>* edges) {
  const Axis axis = AxisInCamera(pen, cam_from_pen);
  const double s0 = o.end_margin_m;
  const double s1 = pen.shaft_length_m - o.end_margin_m;
  if (!(s1 > s0)) return false;
  // The cube's outline, grown by 2 pixels: shaft samples behind it are not
  // the shaft's edge.
  std::vector<Eigen::Vector2d> cube;
  const double h = 0.5 * pen.cube_edge_m;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c((k & 1) ? h : -h, (k & 2) ? h : -h,
                            (k & 4) ? h : -h);
    const Eigen::Vector3d p = cam_from_pen * c;
    if (p.z() <= 1e-3) return false;
    cube.push_back(camera.Project(p));
  }
  cube = geometry::ConvexHull(cube);
  double length_px = 0;
  {
    Eigen::Vector2d a, b, u;
    double z;
    if (!ContourPoint(camera, axis, radius, s0, 1, &a, &u, &z) ||
        !ContourPoint(camera, axis, radius, s1, 1, &b, &u, &z) ||
        (b - a).norm() < o.min_length_px)
      return false;
    length_px = (b - a).norm();
  }
  // Each sample's profile is the mean of `lines` parallel profiles spread
  // over its own stretch of the contour (about one per pixel), so that the
  // whole visible edge, not one line per sample, averages the noise. The
  // contour is straight over a stretch, so the mean step lies where the
  // middle profile's does.
  const double stretch_px = length_px / o.samples_per_side;
  const int lines =
      o.average_along
          ? std::clamp(static_cast<int>(std::ceil(stretch_px)), 1, 8)
          : 1;
  const double line_gap = lines > 1 ? stretch_px / lines : 0.0;
  const double clearance = 2.0 + 0.5 * (lines - 1) * line_gap;
  const double step = 0.5;
  const int n = static_cast<int>(std::ceil(search_px / step)) + 1;
  const double f = 0.5 * (camera.fx + camera.fy);
  for (int side = 0; side < 2; ++side) {
    // Per sample: the steepest step of each polarity (outward brighter,
    // outward darker) and where it is.
    struct Found {
      double s, depth;
      Eigen::Vector2d c, u;
      double strength[2], t[2];
    };
    std::vector<Found> found;
    for (int k = 0; k < o.samples_per_side; ++k) {
      Found fd;
      fd.s = s0 + (s1 - s0) * (k + 0.5) / o.samples_per_side;
      if (!ContourPoint(camera, axis, radius, fd.s, side ? -1 : 1, &fd.c, &fd.u,
                        &fd.depth))
        continue;
      if (geometry::SignedDistanceToConvexPolygon(cube, fd.c) < clearance)
        continue;
      const Eigen::Vector2d tangent(-fd.u.y(), fd.u.x());
      std::vector<double> v(2 * n + 3, 0.0);
      bool inside = true;
      for (int l = 0; l < lines && inside; ++l) {
        const Eigen::Vector2d c =
            fd.c + ((l - 0.5 * (lines - 1)) * line_gap) * tangent;
        for (int j = 0; j < 2 * n + 3 && inside; ++j) {
          const Eigen::Vector2d x = c + ((j - n - 1) * step) * fd.u;
          double value = 0;
          inside = SampleBilinear(gray, x.x(), x.y(), &value);
          v[j] += value / lines;
        }
      }
      if (!inside) continue;
      for (int pol = 0; pol < 2; ++pol) {
        const double sign = pol == 0 ? 1.0 : -1.0;
        int best = -1;
        double g_best = 0;
        for (int j = 1; j + 1 < 2 * n + 3; ++j) {
          const double g = sign * (v[j + 1] - v[j - 1]) / (2 * step);
          if (g > g_best) g_best = g, best = j;
        }
        fd.strength[pol] = g_best;
        fd.t[pol] = 0;
        if (best < 2 || best + 2 >= 2 * n + 3) {
          fd.strength[pol] = 0;  // the step lies at the window's end
          continue;
        }
        const double gm = sign * (v[best] - v[best - 2]) / (2 * step);
        const double gp = sign * (v[best + 2] - v[best]) / (2 * step);
        const double den = gm - 2 * g_best + gp;
        const double off =
            den < 0 ? std::clamp(0.5 * (gm - gp) / den, -0.5, 0.5) : 0.0;
        fd.t[pol] = (best - n - 1 + off) * step;
      }
      found.push_back(fd);
    }
    // The side's polarity: the one with more strong steps (a dark shaft on
    // a light board, or the reverse; the background may change under it).
    int count[2] = {0, 0};
    for (const Found& fd : found)
      for (int pol = 0; pol < 2; ++pol)
        if (fd.strength[pol] >= o.min_edge_dn &&
            fd.strength[pol] >= fd.strength[1 - pol])
          ++count[pol];
    const int pol = count[1] > count[0] ? 1 : 0;
    std::vector<Edge> candidates;
    for (const Found& fd : found) {
      if (fd.strength[pol] < o.min_edge_dn) continue;
      const Eigen::Vector2d e = fd.c + fd.t[pol] * fd.u;
      const Eigen::Vector2d xn = camera.UndistortToNormalized(e);
      candidates.push_back(
          {Eigen::Vector3d(xn.x(), xn.y(), 1.0), fd.s, f / fd.depth});
    }
    // A silhouette line is the trace of a plane through the camera centre:
    // straight in undistorted coordinates. Steps off the line that most
    // samples agree on (a hand's edge, a shadow's, a grout line's) are
    // dropped.
    auto& out = (*edges)[side];
    out.clear();
    const double tol = o.line_tolerance_px / f;
    size_t best_count = 0;
    Eigen::Vector3d best_line = Eigen::Vector3d::Zero();
    for (size_t a = 0; a < candidates.size(); ++a) {
      for (size_t b = a + 1; b < candidates.size(); ++b) {
        Eigen::Vector3d line = candidates[a].ray.cross(candidates[b].ray);
        const double len = line.head<2>().norm();
        if (len < 1e-12) continue;
        line /= len;
        size_t count = 0;
        for (const Edge& c : candidates)
          if (std::abs(line.dot(c.ray)) <= tol) ++count;
        if (count > best_count) best_count = count, best_line = line;
      }
    }
    for (const Edge& c : candidates)
      if (std::abs(best_line.dot(c.ray)) <= tol) out.push_back(c);
    if (static_cast<int>(out.size()) < o.min_samples_per_side) return false;
  }
  return true;
}

// Tangency residuals (pixels) of the edges at a pose.
void Residuals(const PenSpec& pen, const std::array<std::vector<Edge>, 2>& e,
               const Pose& cam_from_pen, double radius,
               std::vector<double>* r) {
  const Axis axis = AxisInCamera(pen, cam_from_pen);
  r->clear();
  for (const auto& side : e)
    for (const Edge& edge : side)
      r->push_back(edge.scale * Tangency(axis, radius, edge.ray));
}

double HuberWeight(double r, double k) {
  const double a = std::abs(r);
  return a <= k ? 1.0 : k / a;
}

double Rms(const std::vector<double>& r, double k) {
  // Robust: residuals beyond k count as k (occluded samples do not decide).
  double ss = 0;
  for (double v : r) ss += std::min(v * v, k * k);
  return r.empty() ? 0.0 : std::sqrt(ss / r.size());
}

}  // namespace

bool ShaftRefineOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = "shaft refinement: " + what;
    return false;
  };
  if (samples_per_side < 4 || samples_per_side > 1000)
    return fail("samples_per_side must be in [4, 1000]");
  if (!(end_margin_m >= 0 && end_margin_m < 1))
    return fail("end_margin_m must be in [0, 1)");
  if (!(min_length_px >= 0)) return fail("min_length_px < 0");
  if (!(search_px >= 1 && search_px <= 50))
    return fail("search_px must be in [1, 50]");
  if (!(min_edge_dn >= 0)) return fail("min_edge_dn < 0");
  if (min_samples_per_side < 2 || min_samples_per_side > samples_per_side)
    return fail("min_samples_per_side must be in [2, samples_per_side]");
  if (!(edge_sigma_px > 0 && corner_sigma_px > 0))
    return fail("edge_sigma_px and corner_sigma_px must be positive");
  if (!(dense_information_scale >= 0 && dense_information_scale <= 1e3))
    return fail("dense_information_scale must be in [0, 1000]");
  if (!(huber_px > 0)) return fail("huber_px must be positive");
  if (!(line_tolerance_px > 0))
    return fail("line_tolerance_px must be positive");
  if (iterations < 1 || iterations > 50)
    return fail("iterations must be in [1, 50]");
  if (!(max_rotation_deg > 0 && max_translation_m > 0))
    return fail("max_rotation_deg and max_translation_m must be positive");
  return true;
}

bool ShaftRefinePose(const cv::Mat& gray, const Camera& camera,
                     const PenSpec& pen,
                     const std::vector<TagObservation>& corners,
                     const ShaftRefineOptions& options, Pose* cam_from_pen,
                     ShaftRefineResult* result, const Mat6* start_information) {
  ShaftRefineResult local;
  ShaftRefineResult& res = result ? *result : local;
  res = ShaftRefineResult();
  if (!options.enabled || gray.empty() || gray.type() != CV_8UC1 ||
      !(pen.shaft_radius_m > 0) || !(pen.shaft_length_m > 0) || corners.empty())
    return false;
  const Pose start = *cam_from_pen;
  const Mat6 prior =
      start_information
          ? Mat6(options.dense_information_scale * *start_information)
          : Mat6(CornerInformation(camera, corners, start) /
                 (options.corner_sigma_px * options.corner_sigma_px));
  const double w_edge = 1.0 / (options.edge_sigma_px * options.edge_sigma_px);
  Pose pose = start;
  double radius = pen.shaft_radius_m;  // fitted with the pose
  std::array<std::vector<Edge>, 2> edges;
  std::vector<double> r, r_plus, r_minus;
  bool searched_start = false;
  for (int search = 0; search < 2; ++search) {
    // The second search looks half as far, around the refined pose.
    const double window = options.search_px * (search ? 0.5 : 1.0);
    if (!FindEdges(gray, camera, pen, options, pose, radius, window, &edges)) {
      if (search == 0) return false;
      break;
    }
    res.edges[0] = static_cast<int>(edges[0].size());
    res.edges[1] = static_cast<int>(edges[1].size());
    if (!searched_start) {
      Residuals(pen, edges, start, pen.shaft_radius_m, &r);
      res.rms_before_px = Rms(r, options.huber_px);
      searched_start = true;
    }
    for (int it = 0; it < options.iterations; ++it) {
      Residuals(pen, edges, pose, radius, &r);
      // The two motions the shaft's image line measures: a turn about the
      // line of sight through the cube's centre (the line's angle) and a
      // shift across both that line of sight and the shaft (the line's
      // offset). The rest (the distance, the tilt towards the camera, the
      // roll about the shaft) stays with the corners and the dense step:
      // the shaft's apparent width and its change along the shaft measure
      // them far worse (a tenth of a pixel of width bias, from blur or a pen
      // a little thicker than its rig, tilts a 14 cm lever by degrees).
      const Eigen::Vector3d sight = pose.translation.normalized();
      const Eigen::Vector3d across =
          sight.cross(AxisInCamera(pen, pose).dir).normalized();
      Eigen::Matrix<double, 6, 2> basis = Eigen::Matrix<double, 6, 2>::Zero();
      basis.block<3, 1>(0, 0) = sight;
      basis.block<3, 1>(3, 1) = across;
      const int m = static_cast<int>(r.size());
      // Jacobian in (turn, shift, radius): central differences for the
      // motions; a residual falls by its scale per metre of radius.
      Eigen::MatrixXd j(m, 3);
      for (int c = 0; c < 2; ++c) {
        const Vec6 d = 1e-6 * basis.col(c);
        Residuals(pen, edges, Perturbed(pose, d), radius, &r_plus);
        Residuals(pen, edges, Perturbed(pose, -d), radius, &r_minus);
        for (int i = 0; i < m; ++i) j(i, c) = (r_plus[i] - r_minus[i]) / 2e-6;
      }
      int i = 0;
      for (const auto& side : edges)
        for (const Edge& edge : side) j(i++, 2) = -edge.scale;
      // The corners' information on the two motions, and a faint prior on
      // the radius at the rig's (a free radius keeps the width's bias out).
      Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
      Eigen::Vector3d g = Eigen::Vector3d::Zero();
      h.topLeftCorner<2, 2>() = basis.transpose() * prior * basis;
      g.head<2>() = basis.transpose() * prior * Difference(start, pose);
      h(2, 2) =
          (options.free_radius ? 1e-6 : 1e6) * w_edge * j.col(2).squaredNorm();
      g(2) = h(2, 2) * (radius - pen.shaft_radius_m);
      for (i = 0; i < m; ++i) {
        const double w = w_edge * HuberWeight(r[i], options.huber_px);
        h += w * j.row(i).transpose() * j.row(i);
        g += w * j.row(i).transpose() * r[i];
      }
      const Eigen::Vector3d x = h.ldlt().solve(-g);
      if (!x.allFinite()) return false;
      pose = Perturbed(pose, basis * x.head<2>());
      radius += x[2];
      if (std::abs(x[0]) < 1e-7 && std::abs(x[1]) < 1e-8) break;
    }
  }
  Residuals(pen, edges, pose, radius, &r);
  res.rms_after_px = Rms(r, options.huber_px);
  const Vec6 moved = Difference(start, pose);
  if (moved.head<3>().norm() * 180 / kPi > options.max_rotation_deg ||
      moved.tail<3>().norm() > options.max_translation_m)
    return false;
  *cam_from_pen = pose;
  res.refined = true;
  return true;
}

int ShaftEdgeSupport(const cv::Mat& gray, const Camera& camera,
                     const PenSpec& pen, const ShaftRefineOptions& options,
                     const Pose& cam_from_pen) {
  if (gray.empty() || gray.type() != CV_8UC1 || !(pen.shaft_radius_m > 0) ||
      !(pen.shaft_length_m > 0))
    return 0;
  ShaftRefineOptions all = options;
  all.min_samples_per_side = 0;  // both sides searched, however few
  std::array<std::vector<Edge>, 2> edges;
  if (!FindEdges(gray, camera, pen, all, cam_from_pen, pen.shaft_radius_m,
                 options.search_px, &edges))
    return 0;
  return static_cast<int>(std::min(edges[0].size(), edges[1].size()));
}

}  // namespace ripple::tracking
