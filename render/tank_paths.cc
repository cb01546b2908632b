#include "render/tank_paths.h"

#include <algorithm>
#include <cmath>

namespace ripple::render::internal {

std::vector<glm::dvec3> CosineDirections(int side) {
  std::vector<glm::dvec3> dirs;
  dirs.reserve(static_cast<size_t>(side) * side);
  for (int v = 0; v < side; ++v) {
    for (int u = 0; u < side; ++u) {
      const double r2 = (v + 0.5) / side, phi = 2.0 * M_PI * (u + 0.5) / side;
      const double r = std::sqrt(r2);
      dirs.emplace_back(r * std::cos(phi), r * std::sin(phi),
                        std::sqrt(1.0 - r2));
    }
  }
  return dirs;
}

namespace {

constexpr double kInf = 1e30;

PathEvent NormalAgainst(PathEvent e, int axis, const glm::dvec3& d) {
  e.n = glm::dvec3(0.0);
  e.n[axis] = d[axis] > 0 ? -1.0 : 1.0;
  return e;
}

// Where o + s d lies inside the box lo..hi over its first `axes` axes:
// s in (in, out), entering across axis `axis` (-1: no axis bounds it);
// `in` is kInf when the ray runs parallel to an axis outside the box.
struct Span {
  double in = -kInf, out = kInf;
  int axis = -1;
};
Span BoxSpan(const glm::dvec3& o, const glm::dvec3& d, const double* lo,
             const double* hi, int axes) {
  Span s;
  for (int k = 0; k < axes; ++k) {
    if (d[k] == 0.0) {
      if (o[k] <= lo[k] || o[k] >= hi[k]) s.in = kInf;
      continue;
    }
    double ta = (lo[k] - o[k]) / d[k], tb = (hi[k] - o[k]) / d[k];
    if (ta > tb) std::swap(ta, tb);
    if (ta > s.in) {
      s.in = ta;
      s.axis = k;
    }
    s.out = std::min(s.out, tb);
  }
  return s;
}

PathEvent AirOutside(const PathTank& t, const glm::dvec3& o,
                     const glm::dvec3& d) {
  // Entering the outer box [-A, A] x [-B, B] x [0, H].
  const double lo[3] = {-t.A, -t.B, 0.0}, hi[3] = {t.A, t.B, t.H};
  const Span box = BoxSpan(o, d, lo, hi, 3);
  const int axis = box.axis;
  PathEvent e;
  if (axis >= 0 && box.in < box.out && box.in > 0.0 && box.in < kInf) {
    e.t = box.in;
    const glm::dvec3 p = o + box.in * d;
    if (axis == 2 && std::abs(p.x) < t.a && std::abs(p.y) < t.b) {
      e.interface = false;  // down through the open top
      e.next = PathMedium::kAirInside;
      return e;
    }
    e.next = PathMedium::kGlass;
    return NormalAgainst(e, axis, d);
  }
  e.ends = true;
  if (d.z < 0.0) {
    e.t = -o.z / d.z;
    e.end = PathEnd::kBoard;
  } else {
    e.end = PathEnd::kSky;
  }
  return e;
}

// Inside the inner column: to its side faces, and the floor or top.
PathEvent InColumn(const PathTank& t, const glm::dvec3& o, const glm::dvec3& d,
                   bool water) {
  const double tx = d.x == 0.0 ? kInf : ((d.x > 0 ? t.a : -t.a) - o.x) / d.x;
  const double ty = d.y == 0.0 ? kInf : ((d.y > 0 ? t.b : -t.b) - o.y) / d.y;
  const double lower = water ? 0.0 : t.W, upper = water ? t.W : t.H;
  const double tz = d.z > 0   ? (upper - o.z) / d.z
                    : d.z < 0 ? (lower - o.z) / d.z
                              : kInf;
  PathEvent e;
  if (tz <= tx && tz <= ty) {
    e.t = std::max(tz, 0.0);
    if (water && d.z < 0) {  // the tank's floor
      e.ends = true;
      e.end = PathEnd::kFloor;
      return e;
    }
    if (!water && d.z > 0) {  // up out of the open top
      e.interface = false;
      e.next = PathMedium::kAirOutside;
      return e;
    }
    e.next = water ? PathMedium::kAirInside : PathMedium::kWater;
    return NormalAgainst(e, 2, d);
  }
  e.t = std::max(std::min(tx, ty), 0.0);
  e.next = PathMedium::kGlass;
  return NormalAgainst(e, tx < ty ? 0 : 1, d);
}

PathEvent InGlass(const PathTank& t, const glm::dvec3& o, const glm::dvec3& d) {
  // Leaving the outer box.
  const double ex = d.x == 0.0 ? kInf : ((d.x > 0 ? t.A : -t.A) - o.x) / d.x;
  const double ey = d.y == 0.0 ? kInf : ((d.y > 0 ? t.B : -t.B) - o.y) / d.y;
  const double ez = d.z > 0 ? (t.H - o.z) / d.z : d.z < 0 ? -o.z / d.z : kInf;
  const double t_exit = std::max(std::min({ex, ey, ez}), 0.0);
  // Entering the inner column |x| < a, |y| < b.
  const double lo[2] = {-t.a, -t.b}, hi[2] = {t.a, t.b};
  const Span column = BoxSpan(o, d, lo, hi, 2);
  PathEvent e;
  if (column.axis >= 0 && column.in < column.out && column.in > 0.0 &&
      column.in < t_exit) {
    e.t = column.in;
    const double z = o.z + column.in * d.z;
    e.next = z < t.W ? PathMedium::kWater : PathMedium::kAirInside;
    return NormalAgainst(e, column.axis, d);
  }
  e.t = t_exit;
  if (ez <= ex && ez <= ey && d.z < 0) {
    e.ends = true;
    e.end = PathEnd::kUnderGlass;
    return e;
  }
  e.next = PathMedium::kAirOutside;
  return NormalAgainst(e, ex <= ey && ex <= ez ? 0 : (ey <= ez ? 1 : 2), d);
}

}  // namespace

PathTank MakePathTank(const TankGeometry& tank, double glass_thickness_m,
                      double water_ior, double glass_ior,
                      const glm::dvec3& absorption_per_m) {
  PathTank t;
  t.a = 0.5 * tank.size_x;
  t.b = 0.5 * tank.size_y;
  t.A = t.a + glass_thickness_m;
  t.B = t.b + glass_thickness_m;
  t.H = tank.wall_height;
  t.W = std::clamp(static_cast<double>(tank.water_level), 1e-6, t.H - 1e-6);
  t.n_water = water_ior;
  t.n_glass = glass_ior;
  t.sigma = absorption_per_m;
  return t;
}

PathTank MakePathTank(const TankGeometry& tank, const WaterOptics& optics) {
  return MakePathTank(tank, optics.glass_thickness_m, optics.ior,
                      optics.glass_ior, glm::dvec3(optics.absorption_per_m));
}

PathEvent NextPathEvent(const PathTank& t, PathMedium m, const glm::dvec3& o,
                        const glm::dvec3& d) {
  switch (m) {
    case PathMedium::kAirOutside:
      return AirOutside(t, o, d);
    case PathMedium::kAirInside:
      return InColumn(t, o, d, false);
    case PathMedium::kWater:
      return InColumn(t, o, d, true);
    case PathMedium::kGlass:
      break;
  }
  return InGlass(t, o, d);
}

}  // namespace ripple::render::internal
