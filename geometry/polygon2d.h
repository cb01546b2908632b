// Plane polygons (Eigen, header-only).
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

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_POLYGON2D_H_
