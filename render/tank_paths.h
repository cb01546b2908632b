// Light paths through the glass tank of flat water (internal to render/):
// the walls are glass slabs `glass_thickness_m` thick outside the inner size
// and wall_height tall, standing on the board (the glass is the outer box
// less the inner column, its corners solid), the water is at rest up to
// water_level. A path is followed through every interface, splitting by the
// exact (unpolarised) Fresnel reflectance, with total internal reflection and
// Beer-Lambert absorption in the water, until a branch's weight falls under
// 1e-3 or it has met 24 interfaces. The board's light around
// the tank (board_light.h) and the floor's light near the walls
// (caustics_kernels.h) are both traced here.
//
// Frames and units: tank frame (origin at the tank's centre, z up, the board
// and the tank's floor at z = 0), metres.
#ifndef RIPPLE_RENDER_TANK_PATHS_H_
#define RIPPLE_RENDER_TANK_PATHS_H_

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <vector>

#include "render/optics.h"
#include "render/scene.h"

namespace ripple::render::internal {

// The flat tank: inner half sizes a, b; outer A, B; walls H tall; water up
// to W; refractive indices and the water's absorption per band (1/m).
struct PathTank {
  double a = 0, b = 0, A = 0, B = 0, H = 0, W = 0;
  double n_water = 1.333, n_glass = 1.5;
  glm::dvec3 sigma{0.0};
};
PathTank MakePathTank(const TankGeometry& tank, double glass_thickness_m,
                      double water_ior, double glass_ior,
                      const glm::dvec3& absorption_per_m);
PathTank MakePathTank(const TankGeometry& tank, const WaterOptics& optics);

enum class PathMedium { kAirOutside, kAirInside, kGlass, kWater };
enum class PathEnd { kSky, kBoard, kUnderGlass, kFloor };

// How a branch came into the water: kNone (never), kSurface (first through
// the surface, no interface met since: the refracted light of the surface
// alone), kSurfaceThenGlass (first through the surface, then at least one
// more interface: mirrored by a wall, or out and back in), kWall (first
// through a wall's inner face, straight from its outer face: light that
// came in through the wall), kWallIndirect (first through a wall's inner
// face after a reflection inside the glass or having entered it from the
// air inside the tank: the light that crossed a wall facing away above the
// water and came back in below the water line after its outer face's
// reflection, and the light a wall facing the light let in after
// reflections between its faces). kGlassIndirect: not in the water yet, in
// or past such a reflection or entry.
enum class PathEntry {
  kNone,
  kGlassIndirect,
  kSurface,
  kSurfaceThenGlass,
  kWall,
  kWallIndirect
};

// The next interface or end of a path in one medium.
struct PathEvent {
  double t = 1e30;
  glm::dvec3 n{0.0};  // the interface's normal, against the ray
  PathMedium next = PathMedium::kAirOutside;
  bool interface = true;  // false: the medium changes without one (the
                          // open top of the tank), or the path ends
  bool ends = false;
  PathEnd end = PathEnd::kSky;
};
PathEvent NextPathEvent(const PathTank& t, PathMedium m, const glm::dvec3& o,
                        const glm::dvec3& d);

namespace tank_paths_detail {
constexpr double kStep = 1e-7;       // metres past an interface
constexpr double kMinWeight = 1e-3;  // a branch lighter than this ends
constexpr int kMaxDepth = 24;        // interfaces along one path

inline double IndexOf(const PathTank& t, PathMedium m) {
  return m == PathMedium::kWater ? t.n_water
                                 : (m == PathMedium::kGlass ? t.n_glass : 1.0);
}

// The entry state of the branch that crosses from `from` into `to` (or
// stays, `to` == `from`, by reflection).
inline PathEntry After(PathEntry entry, PathMedium from, PathMedium to) {
  if (entry == PathEntry::kNone || entry == PathEntry::kGlassIndirect) {
    if (to == PathMedium::kWater && from != PathMedium::kWater) {
      if (from == PathMedium::kAirInside) return PathEntry::kSurface;
      return entry == PathEntry::kGlassIndirect ? PathEntry::kWallIndirect
                                                : PathEntry::kWall;
    }
    // Into a wall from the air inside the tank, or reflected inside one.
    if (to == PathMedium::kGlass &&
        (from == PathMedium::kAirInside || from == PathMedium::kGlass))
      return PathEntry::kGlassIndirect;
    return entry;
  }
  return entry == PathEntry::kSurface ? PathEntry::kSurfaceThenGlass : entry;
}
}  // namespace tank_paths_detail

// side x side directions over the upper unit hemisphere, cosine-weighted
// and stratified over the unit square (r^2 and the azimuth at cell
// centres); an even side makes the set its own mirror image in x and in y.
std::vector<glm::dvec3> CosineDirections(int side);

// The summed weights of the branches of traced paths by where they end: the
// sky per band, the board, the floor and the board under the glass in
// green. Pass it to TracePath as `end`.
struct PathEndSums {
  glm::dvec3 sky{0.0};
  double board = 0, floor = 0, under_glass = 0;
  void operator()(PathEnd kind, const glm::dvec3&, const glm::dvec3& w,
                  PathEntry) {
    switch (kind) {
      case PathEnd::kSky:
        sky += w;
        break;
      case PathEnd::kBoard:
        board += w.y;
        break;
      case PathEnd::kFloor:
        floor += w.y;
        break;
      case PathEnd::kUnderGlass:
        under_glass += w.y;
        break;
    }
  }
};

// Follows o + s d from medium m with weight w per band, splitting at every
// interface, and calls end(kind, point, weight, entry) for each branch that
// reaches the sky (point: where it left the last interface), the board
// outside, the board under the glass or the tank's floor.
template <class F>
void TracePath(const PathTank& t, glm::dvec3 o, glm::dvec3 d, PathMedium m,
               glm::dvec3 w, F& end, PathEntry entry = PathEntry::kNone,
               int depth = 0) {
  using namespace tank_paths_detail;
  while (true) {
    const PathEvent e = NextPathEvent(t, m, o, d);
    if (m == PathMedium::kWater) {
      const double s = std::min(e.t, 1.0);
      w *= glm::dvec3(std::exp(-t.sigma.x * s), std::exp(-t.sigma.y * s),
                      std::exp(-t.sigma.z * s));
    }
    if (e.ends) {
      end(e.end, e.end == PathEnd::kSky ? o : o + e.t * d, w, entry);
      return;
    }
    const glm::dvec3 p = o + e.t * d;
    if (!e.interface) {
      o = p + kStep * d;
      m = e.next;
      continue;
    }
    if (++depth > kMaxDepth) return;
    const double n1 = IndexOf(t, m), n2 = IndexOf(t, e.next);
    const double ci = -glm::dot(d, e.n);
    const double f = FresnelReflectance(ci, n1, n2);
    const glm::dvec3 r = d + 2.0 * ci * e.n;
    if (f < 1.0 && (1.0 - f) * std::max({w.x, w.y, w.z}) > kMinWeight) {
      const double eta = n1 / n2;
      const double k = 1.0 - eta * eta * (1.0 - ci * ci);
      const glm::dvec3 tr = eta * d + (eta * ci - std::sqrt(k)) * e.n;
      TracePath(t, p + kStep * tr, tr, e.next, w * (1.0 - f), end,
                After(entry, m, e.next), depth);
    }
    w *= f;
    if (std::max({w.x, w.y, w.z}) <= kMinWeight) return;
    entry = After(entry, m, m);
    o = p + kStep * r;
    d = r;
  }
}

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_TANK_PATHS_H_
