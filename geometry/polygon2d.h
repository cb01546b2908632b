// Plane polygons (Eigen, header-only): the signed distance to a convex
// polygon and the convex hull, shared by the synthetic renderer and the
// light estimator.
#ifndef RIPPLE_GEOMETRY_POLYGON2D_H_
#define RIPPLE_GEOMETRY_POLYGON2D_H_

#include <Eigen/Core>
#include <algorithm>
#include <vector>

namespace ripple::geometry {

// Distance from `p` to a counter-clockwise convex polygon's boundary,
// negative inside (a polygon of fewer than 3 vertices has no inside).
inline double SignedDistanceToConvexPolygon(
    const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  double d = 1e300;
  bool inside = poly.size() >= 3;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d e = poly[i] - poly[j];
    const double u = std::clamp(
        (p - poly[j]).dot(e) / std::max(e.squaredNorm(), 1e-30), 0.0, 1.0);
    d = std::min(d, (p - (poly[j] + u * e)).norm());
    if (e.x() * (p - poly[j]).y() - e.y() * (p - poly[j]).x() < 0)
      inside = false;
  }
  return inside ? -d : d;
}

// The convex hull of `pts`, counter-clockwise, without collinear points
// (Andrew's monotone chain); fewer than 3 points come back sorted.
inline std::vector<Eigen::Vector2d> ConvexHull(
    std::vector<Eigen::Vector2d> pts) {
  std::sort(pts.begin(), pts.end(),
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
              return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
            });
  if (pts.size() < 3) return pts;
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a,
                  const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_POLYGON2D_H_
