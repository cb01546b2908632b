#include "render/coarse_grid.h"

#include <algorithm>
#include <cmath>

#include "render/camera.h"
#include "render/frame_state.h"

namespace ripple::render::internal {

glm::ivec4 CoarseGrid::RectOut(const glm::ivec4& r, int pad) const {
  if (r.z <= 0 || r.w <= 0) return {0, 0, 0, 0};
  const int x0 =
      std::clamp(static_cast<int>(std::floor(r.x * scale.x)) - pad, 0, width);
  const int y0 =
      std::clamp(static_cast<int>(std::floor(r.y * scale.y)) - pad, 0, height);
  const int x1 = std::clamp(
      static_cast<int>(std::ceil((r.x + r.z) * scale.x)) + pad, 0, width);
  const int y1 = std::clamp(
      static_cast<int>(std::ceil((r.y + r.w) * scale.y)) + pad, 0, height);
  return {x0, y0, x1 - x0, y1 - y0};
}

CoarseGrid CoarseGridFor(int width, int height, int max_columns) {
  CoarseGrid g;
  if (max_columns < 0) {
    max_columns = kAutoMaxColumns;
  }
  if (max_columns <= 0 || width <= max_columns || height <= 0) return g;
  g.width = max_columns;
  g.height = std::max(
      1, static_cast<int>(std::lround(double(height) * max_columns / width)));
  g.scale = {double(g.width) / width, double(g.height) / height};
  return g;
}

std::vector<glm::dvec2> ConvexHull(std::vector<glm::dvec2> p) {
  std::sort(p.begin(), p.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto cross = [](const glm::dvec2& o, const glm::dvec2& a,
                  const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower chain
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper chain
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);  // the last point is the first
  return hull;
}

std::vector<glm::dvec2> GrownBoxHull(const glm::dmat4& clip_from_tank,
                                     double size_x, double size_y, double z0,
                                     double z1, int width, int height,
                                     double grow) {
  glm::dvec3 corners[8];
  BoxCorners(size_x, size_y, z0, z1, corners);
  std::vector<glm::dvec2> points;
  points.reserve(32);
  for (const glm::dvec3& corner : corners) {
    const glm::dvec4 c = clip_from_tank * glm::dvec4(corner, 1.0);
    if (c.w <= 1e-6) return {};
    const glm::dvec2 w = WindowFromClip(c, width, height);
    for (int s = 0; s < 4; ++s) {
      points.push_back(w +
                       glm::dvec2(s & 1 ? grow : -grow, s & 2 ? grow : -grow));
    }
  }
  return ConvexHull(std::move(points));
}

}  // namespace ripple::render::internal
