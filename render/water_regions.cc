#include "render/water_regions.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace ripple::render::internal {
namespace {

// The lowest and highest the surface is this frame (the height texture's
// decoded range around the rest level, a tenth of a millimetre wider).
double SurfaceLow(const FrameState& f) {
  const HeightFieldInfo& h = f.height;
  return f.scene->tank.water_level +
         std::min(h.decode_offset.x, h.decode_offset.x + h.decode_scale.x) -
         1e-4;
}
double SurfaceHigh(const FrameState& f) {
  const HeightFieldInfo& h = f.height;
  return f.scene->tank.water_level +
         std::max(h.decode_offset.x, h.decode_offset.x + h.decode_scale.x) +
         1e-4;
}

glm::ivec4 WholeWindow(const FrameState& f) {
  return {0, 0, f.k->width, f.k->height};
}

// The tank point at height z on the camera ray through window position
// `window`; false when the ray does not reach that plane in front of the
// camera.
bool OnPlane(const FrameState& f, const glm::dvec2& window, double z,
             glm::dvec3* p) {
  const Intrinsics& k = *f.k;
  const glm::dvec2 px = PixelFromWindow(window);
  const glm::dvec3 ray_cam((px.x - k.cx) / k.fx, (px.y - k.cy) / k.fy, 1.0);
  const glm::dvec3 d = glm::dmat3(f.tank_from_cam) * ray_cam;
  const glm::dvec3& c = f.cam_in_tank;
  if (std::abs(d.z) < 1e-9) return false;
  const double s = (z - c.z) / d.z;
  if (!(s > 0)) return false;
  *p = c + s * d;
  return true;
}

// Window rectangle of the surface points (z at the surface's lowest and
// highest) within `reach` metres horizontally of the tank points `q`.
glm::ivec4 SurfaceNear(const FrameState& f, const std::vector<glm::dvec3>& q,
                       double reach) {
  std::vector<glm::dvec3> pts;
  pts.reserve(q.size() * 8);
  const double z_lo = SurfaceLow(f), z_hi = SurfaceHigh(f);
  for (const glm::dvec3& p : q) {
    for (const double z : {z_lo, z_hi}) {
      for (int i = 0; i < 4; ++i) {
        pts.emplace_back(p.x + (i & 1 ? reach : -reach),
                         p.y + (i & 2 ? reach : -reach), z);
      }
    }
  }
  return PointsRect(f.clip_from_tank, pts.data(), static_cast<int>(pts.size()),
                    2, f.k->width, f.k->height);
}

// The window rectangle's four corners (grown by `grow` pixels) on the
// plane z (or on both planes z0 and z1); false if a corner's ray misses.
bool CornersOnPlanes(const FrameState& f, const glm::ivec4& r, double grow,
                     std::initializer_list<double> planes,
                     std::vector<glm::dvec3>* out) {
  for (const double z : planes) {
    for (int i = 0; i < 4; ++i) {
      const glm::dvec2 w(i & 1 ? r.x + r.z + grow : r.x - grow,
                         i & 2 ? r.y + r.w + grow : r.y - grow);
      glm::dvec3 p;
      if (!OnPlane(f, w, z, &p)) return false;
      out->push_back(p);
    }
  }
  return true;
}

bool Empty(const glm::ivec4& r) { return r.z <= 0 || r.w <= 0; }

// The steepest surface slope |grad h| this frame (the height texture's
// decoded range bounds each component).
double SlopeMax(const FrameState& f) {
  const HeightFieldInfo& h = f.height;
  const double sx = std::max(std::abs(h.decode_offset.y),
                             std::abs(h.decode_offset.y + h.decode_scale.y));
  const double sy = std::max(std::abs(h.decode_offset.z),
                             std::abs(h.decode_offset.z + h.decode_scale.z));
  return std::hypot(sx, sy);
}

// The 16 directions a normal is tilted in (ForRefractedRays).
const std::array<glm::dvec2, 16> kAzimuths = [] {
  std::array<glm::dvec2, 16> a;
  for (int i = 0; i < 16; ++i) {
    const double phi = i * (2.0 * M_PI / 16.0);
    a[i] = {std::cos(phi), std::sin(phi)};
  }
  return a;
}();

// Calls `ray(r)` for rays refracted into the water: the camera's rays to
// the tank's corners at the rest level (the steepest incidence is at the
// farthest corner), the normal tilted by up to `slope` in 16 directions.
// False when one could run near the horizontal (then no bound is made).
template <typename F>
bool ForRefractedRays(const FrameState& f, double slope, F&& ray) {
  const TankGeometry& t = f.scene->tank;
  const double eta = 1.0 / f.optics->ior;
  for (int c = 0; c < 4; ++c) {
    const glm::dvec3 corner((c & 1 ? 0.5 : -0.5) * t.size_x,
                            (c & 2 ? 0.5 : -0.5) * t.size_y, t.water_level);
    const glm::dvec3 v = glm::normalize(corner - f.cam_in_tank);
    for (int s = 0; s <= 2; ++s) {
      const double m = slope * s / 2.0;
      for (int a = 0; a < (s == 0 ? 1 : 16); ++a) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(-m * kAzimuths[a], 1));
        const glm::dvec3 r = glm::refract(v, n, eta);
        if (!(r.z < -0.1)) return false;
        ray(r);
      }
    }
  }
  return true;
}

// The largest horizontal travel per unit depth of a ray refracted into the
// water (ForRefractedRays), 10 % over the samples; infinity when a ray
// could run near the horizontal.
double RefractedReach(const FrameState& f, double slope) {
  double k = 0;
  const bool bounded = ForRefractedRays(f, slope, [&](const glm::dvec3& r) {
    k = std::max(k, std::hypot(r.x, r.y) / -r.z);
  });
  return bounded ? 1.1 * k : std::numeric_limits<double>::infinity();
}

// The same towards each wall (-x, +x, -y, +y; 0 for a wall every ray moves
// away from); false when a ray could run near the horizontal.
bool RefractedTravel(const FrameState& f, double slope, double travel[4]) {
  for (int w = 0; w < 4; ++w) travel[w] = 0;
  return ForRefractedRays(f, slope, [&](const glm::dvec3& r) {
    for (int w = 0; w < 4; ++w) {
      const double toward = (w & 1 ? 1.0 : -1.0) * r[w / 2] / -r.z;
      travel[w] = std::max(travel[w], 1.1 * toward);
    }
  });
}

// How far along a wall a ray the glass totally reflects moves inside it:
// 2 d tan(theta_g) at most, and theta_g < asin(n_water / n_glass).
double GlassShift(const FrameState& f) {
  const double sin_g = std::min(f.optics->ior / f.optics->glass_ior, 0.999f);
  return 2.0 * f.optics->glass_thickness_m * sin_g /
         std::sqrt(1.0 - sin_g * sin_g);
}

// The horizontal travel per unit height of a ray out through a vertical
// wall, for rays of horizontal travel k per unit depth in the water: the
// ray's vertical component grows by the index, |d_z| = n / sqrt(1 + k^2) at
// the shallowest. False when that ray could run near the horizontal.
bool OutTravel(const FrameState& f, double k, double* k_out) {
  const double out_z = std::min(1.0, f.optics->ior / std::sqrt(1.0 + k * k));
  if (!std::isfinite(k) || out_z < 0.1) return false;
  *k_out = std::sqrt(1.0 - out_z * out_z) / out_z;
  return true;
}

// Half a step of the slopes' 8-bit code: what the tile maxima may be short
// of a lookup's slope.
double SlopeCodeStep(const HeightFieldInfo& h) {
  return 0.5 * std::hypot(h.decode_scale.y, h.decode_scale.z) / 255.0;
}

// Calls `tile(t0, t1, slope)` for each slope tile of the field: its tank
// rectangle (the border tiles reach out to the walls and beyond, where the
// lookups are clamped) and its steepest slope, the code's rounding added.
template <typename F>
void ForSlopeTiles(const HeightFieldInfo& h, F&& tile) {
  const double code_step = SlopeCodeStep(h);
  const glm::dvec2 origin = -0.5 * glm::dvec2(h.extent);
  constexpr double kFar = 1e3;  // metres: "unbounded" for border tiles
  for (int j = 0; j < h.tiles_y; ++j) {
    for (int i = 0; i < h.tiles_x; ++i) {
      glm::dvec2 t0 = origin + glm::dvec2(i, j) * double(h.tile_m);
      glm::dvec2 t1 = t0 + glm::dvec2(h.tile_m);
      if (i == 0) t0.x = -kFar;
      if (j == 0) t0.y = -kFar;
      if (i == h.tiles_x - 1) t1.x = kFar;
      if (j == h.tiles_y - 1) t1.y = kFar;
      tile(t0, t1,
           h.tile_slope[static_cast<size_t>(j) * h.tiles_x + i] + code_step);
    }
  }
}

}  // namespace

glm::ivec4 IntersectRect(const glm::ivec4& a, const glm::ivec4& b) {
  const int x0 = std::max(a.x, b.x), y0 = std::max(a.y, b.y);
  const int x1 = std::min(a.x + a.z, b.x + b.z);
  const int y1 = std::min(a.y + a.w, b.y + b.w);
  if (x1 <= x0 || y1 <= y0) return {0, 0, 0, 0};
  return {x0, y0, x1 - x0, y1 - y0};
}

glm::ivec4 PenRefractionRect(const FrameState& f, const glm::dvec3& tip,
                             const glm::dvec3& axis, double length,
                             double radius, double margin) {
  const double top = SurfaceHigh(f);
  if (!(f.cam_in_tank.z > top + 1e-3)) return WholeWindow(f);
  // The shaft's part under the highest surface, as a box grown by its
  // radius and margin.
  const double g = radius + margin;
  glm::dvec3 a = tip - margin * axis, b = tip + (length + margin) * axis;
  const double z_cut = top + g;
  if (a.z > z_cut && b.z > z_cut) return {0, 0, 0, 0};
  if (a.z > z_cut) a += (b - a) * ((z_cut - a.z) / (b.z - a.z));
  if (b.z > z_cut) b += (a - b) * ((z_cut - b.z) / (a.z - b.z));
  glm::dvec3 lo = glm::min(a, b) - g, hi = glm::max(a, b) + g;
  hi.z = std::min(hi.z, top);
  if (lo.z > top) return {0, 0, 0, 0};
  const double k = RefractedReach(f, SlopeMax(f));
  if (!std::isfinite(k)) return WholeWindow(f);
  // Each corner P: the surface points within depth(P) * k of the point
  // above P (the deepest corner's depth for all).
  std::vector<glm::dvec3> q;
  for (int i = 0; i < 4; ++i)
    q.emplace_back(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, top);
  return SurfaceNear(f, q, k * (top - lo.z) + 0.001);
}

glm::ivec4 MirroredObjectsRect(const FrameState& f) {
  const SceneInputs& scene = *f.scene;
  const double two_level = 2.0 * scene.tank.water_level;
  std::vector<glm::dvec3> corners;
  auto mirror = [&](const glm::dvec3* c) {
    for (int i = 0; i < 8; ++i)
      corners.emplace_back(c[i].x, c[i].y, two_level - c[i].z);
  };
  for (const Obstacle& o : scene.obstacles) {
    glm::dvec3 c[8];
    ObstacleBoxCorners(o, c);
    mirror(c);
  }
  if (scene.pen_visible) {
    // The cube centred on the pen origin, the shaft along -z from its face.
    const PenGeometry& g = scene.pen;
    const double h = std::max<double>(0.5 * g.cube_edge, g.shaft_radius);
    const double z0 = -0.5 * g.cube_edge - g.shaft_length - g.shaft_radius;
    glm::dvec3 c[8];
    for (int i = 0; i < 8; ++i) {
      const glm::dvec4 p(i & 1 ? h : -h, i & 2 ? h : -h,
                         i & 4 ? 0.5 * g.cube_edge : z0, 1.0);
      c[i] = glm::dvec3(scene.tank_from_pen * p);
    }
    mirror(c);
  }
  if (corners.empty()) return {0, 0, 0, 0};
  // The mirror is a quarter of the output each way, filtered: a texel and
  // its neighbour's reach.
  return PointsRect(f.clip_from_tank, corners.data(),
                    static_cast<int>(corners.size()), 8, f.k->width,
                    f.k->height);
}

glm::ivec4 MirrorLookupRect(const FrameState& f,
                            const glm::ivec4& mirror_window) {
  if (Empty(mirror_window)) return {0, 0, 0, 0};
  // The lookup point (the surface point moved by the slope) on either
  // surface height, then the surface points within reach of it.
  std::vector<glm::dvec3> q;
  if (!CornersOnPlanes(f, mirror_window, 0.0, {SurfaceLow(f), SurfaceHigh(f)},
                       &q)) {
    return WholeWindow(f);
  }
  const HeightFieldInfo& h = f.height;
  if (h.tile_slope == nullptr) {
    return SurfaceNear(f, q, 2.0 * kMirrorDepth_m * SlopeMax(f) + 0.001);
  }
  // Tile by tile, with the tile's own steepest slope: the surface points of
  // a tile within its reach of the lookup points' box. The field's border
  // tiles reach out to the tank's walls and beyond (clamped lookups).
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const glm::dvec3& p : q) {
    lo = glm::min(lo, glm::dvec2(p));
    hi = glm::max(hi, glm::dvec2(p));
  }
  std::vector<glm::dvec3> pts;
  const double z_lo = SurfaceLow(f), z_hi = SurfaceHigh(f);
  ForSlopeTiles(h,
                [&](const glm::dvec2& t0, const glm::dvec2& t1, double slope) {
                  const double reach = 2.0 * kMirrorDepth_m * slope + 0.001;
                  const glm::dvec2 a = glm::max(t0, lo - reach);
                  const glm::dvec2 b = glm::min(t1, hi + reach);
                  if (!(a.x <= b.x && a.y <= b.y)) return;
                  for (const double z : {z_lo, z_hi}) {
                    for (int c = 0; c < 4; ++c)
                      pts.emplace_back(c & 1 ? b.x : a.x, c & 2 ? b.y : a.y, z);
                  }
                });
  if (pts.empty()) return {0, 0, 0, 0};
  return PointsRect(f.clip_from_tank, pts.data(), static_cast<int>(pts.size()),
                    2, f.k->width, f.k->height);
}

glm::ivec4 WallFreeRect(const FrameState& f) {
  const TankGeometry& t = f.scene->tank;
  const glm::dvec3& c = f.cam_in_tank;
  const double z_lo = SurfaceLow(f), z_hi = SurfaceHigh(f);
  if (!(c.z > std::max<double>(t.wall_height, z_hi) + 1e-3)) return {};
  double travel[4];
  if (!RefractedTravel(f, SlopeMax(f), travel)) return {};
  const double half[2] = {0.5 * t.size_x, 0.5 * t.size_y};
  double lo[2], hi[2];
  for (int a = 0; a < 2; ++a) {
    // The refracted ray's reach towards each wall over the deepest water,
    // plus a millimetre.
    lo[a] = -half[a] + travel[2 * a] * z_hi + 0.001;
    hi[a] = half[a] - travel[2 * a + 1] * z_hi - 0.001;
    // A wall the camera is outside of: its glass is crossed by the view ray
    // to a surface point p (height z) when the ray is under the wall's top
    // H at the glass's outer face W = half + d. Along the axis, with u =
    // side * p and C = side * c, the ray's height there is z + (c.z - z)
    // (W - u) / (C - u), which is at least H for u <= ((c.z - z) W - (H -
    // z) C) / (c.z - H); the lower of the two surface planes' bounds.
    const double w_out = half[a] + f.optics->glass_thickness_m;
    for (const double side : {-1.0, 1.0}) {
      const double cc = side * c[a];
      if (!(cc > w_out)) continue;
      double u_max = std::numeric_limits<double>::infinity();
      for (const double z : {z_lo, z_hi}) {
        u_max = std::min(u_max, ((c.z - z) * w_out - (t.wall_height - z) * cc) /
                                    (c.z - t.wall_height));
      }
      u_max -= 0.001;
      if (side > 0)
        hi[a] = std::min(hi[a], u_max);
      else
        lo[a] = std::max(lo[a], -u_max);
    }
    if (!(lo[a] < hi[a])) return {};
  }
  // The box's four corners on each surface plane, on screen.
  glm::dvec2 on_screen[8];
  for (int plane = 0; plane < 2; ++plane) {
    const double z = plane ? z_hi : z_lo;
    for (int i = 0; i < 4; ++i) {
      const glm::dvec4 clip =
          f.clip_from_tank *
          glm::dvec4(i & 1 ? hi[0] : lo[0], i & 2 ? hi[1] : lo[1], z, 1.0);
      if (!(clip.w > 1e-6)) return {};
      on_screen[plane * 4 + i] = WindowFromClip(clip, f.k->width, f.k->height);
    }
  }
  // Each plane's quadrilateral (convex, its corners a perspective image of
  // a rectangle's): the rectangle between its two leftmost and two
  // rightmost corners' inner x and its two lowest and two highest corners'
  // inner y; both planes' overlap.
  double x0 = -1e300, x1 = 1e300, y0 = -1e300, y1 = 1e300;
  for (int plane = 0; plane < 2; ++plane) {
    double xs[4], ys[4];
    for (int i = 0; i < 4; ++i) {
      xs[i] = on_screen[plane * 4 + i].x;
      ys[i] = on_screen[plane * 4 + i].y;
    }
    std::sort(xs, xs + 4);
    std::sort(ys, ys + 4);
    x0 = std::max(x0, xs[1]);
    x1 = std::min(x1, xs[2]);
    y0 = std::max(y0, ys[1]);
    y1 = std::min(y1, ys[2]);
  }
  // The overlap of two convex regions is convex: a rectangle lies in it if
  // its corners do (each corner's ray on both planes inside the box). For a
  // view across a corner of the tank the quadrilaterals are diamonds, and
  // the rectangle above pokes out of them: it is shrunk about its centre,
  // a tenth at a time, until it fits.
  auto fits = [&](int x0i, int y0i, int x1i, int y1i) {
    for (int i = 0; i < 4; ++i) {
      const glm::dvec2 w(i & 1 ? x1i : x0i, i & 2 ? y1i : y0i);
      for (const double z : {z_lo, z_hi}) {
        glm::dvec3 p;
        if (!OnPlane(f, w, z, &p)) return false;
        if (p.x < lo[0] || p.x > hi[0] || p.y < lo[1] || p.y > hi[1])
          return false;
      }
    }
    return true;
  };
  const glm::dvec2 centre(0.5 * (x0 + x1), 0.5 * (y0 + y1));
  const glm::dvec2 half_size(0.5 * (x1 - x0), 0.5 * (y1 - y0));
  for (int step = 0; step < 10; ++step) {
    const glm::dvec2 a = centre - half_size * (1.0 - 0.1 * step);
    const glm::dvec2 b = centre + half_size * (1.0 - 0.1 * step);
    // Inward to whole 4 x 4 blocks, inside the window.
    const int ix0 = (std::max(0, static_cast<int>(std::ceil(a.x))) + 3) & ~3;
    const int iy0 = (std::max(0, static_cast<int>(std::ceil(a.y))) + 3) & ~3;
    const int ix1 =
        std::min(f.k->width, static_cast<int>(std::floor(b.x))) & ~3;
    const int iy1 =
        std::min(f.k->height, static_cast<int>(std::floor(b.y))) & ~3;
    if (ix1 <= ix0 || iy1 <= iy0) return {};
    if (fits(ix0, iy0, ix1, iy1)) return {ix0, iy0, ix1 - ix0, iy1 - iy0};
  }
  return {};
}

glm::ivec4 PlateLookupRect(const FrameState& f,
                           const glm::ivec4& image_window) {
  if (Empty(image_window)) return {0, 0, 0, 0};
  // Image pixels x .. x + w - 1 are window positions x .. x + w; one more
  // pixel each way for the mask's filtering.
  std::vector<glm::dvec3> q;
  if (!CornersOnPlanes(f, image_window, 1.0, {0.0}, &q)) return WholeWindow(f);
  const double depth = SurfaceHigh(f);
  const double k = RefractedReach(f, SlopeMax(f));
  // Out through a wall, and along it inside the glass.
  double k_out;
  if (!OutTravel(f, k, &k_out)) return WholeWindow(f);
  return SurfaceNear(f, q, (k + k_out) * depth + GlassShift(f) + 0.001);
}

namespace {

struct Box2 {
  glm::dvec2 lo, hi;  // tank x, y
};

// The surface boxes holding every surface point whose refracted lookup may
// land on the board box [lo, hi], for rays of horizontal travel `travel`
// per unit depth towards each wall (RefractedTravel) and `k_out` per unit
// height out through a wall (OutTravel): the box moved back by the travel
// (straight down), its mirror image across each wall a ray comes within
// reach of (a side wall's glass mirrors the ray, which lands as if it went
// on to the mirror image of its floor point), and the strip along a wall
// the box reaches past (out through the wall to the board beyond it).
void LookupSources(const FrameState& f, const glm::dvec2& lo,
                   const glm::dvec2& hi, const double travel[4], double k_out,
                   std::vector<Box2>* out) {
  const TankGeometry& t = f.scene->tank;
  const double depth = SurfaceHigh(f);
  const double glass_shift = GlassShift(f);
  // A refracted ray from surface point p lands at p + D, D.x within
  // [-travel[0], travel[1]] * depth and D.y within [-travel[2], travel[3]]
  // * depth: p lies in the box moved back by D.
  auto moved_back = [&](const glm::dvec2& a, const glm::dvec2& b) {
    out->push_back(
        {a - glm::dvec2(travel[1], travel[3]) * depth - glass_shift,
         b + glm::dvec2(travel[0], travel[2]) * depth + glass_shift});
  };
  // A ray that lands straight down or after a wall's mirror lands in the
  // tank (or under a wall's glass): only that part of the box counts.
  const glm::dvec2 half(0.5 * t.size_x, 0.5 * t.size_y);
  const glm::dvec2 in_lo =
      glm::max(lo, -half - double(f.optics->glass_thickness_m));
  const glm::dvec2 in_hi =
      glm::min(hi, half + double(f.optics->glass_thickness_m));
  if (in_lo.x <= in_hi.x && in_lo.y <= in_hi.y) {
    moved_back(in_lo, in_hi);
    for (int axis = 0; axis < 2; ++axis) {
      if (in_hi[axis] >
          half[axis] - travel[2 * axis + 1] * depth - glass_shift) {
        glm::dvec2 a = in_lo, b = in_hi;
        a[axis] = 2.0 * half[axis] - in_hi[axis];
        b[axis] = 2.0 * half[axis] - in_lo[axis];
        moved_back(a, b);
      }
      if (in_lo[axis] < -half[axis] + travel[2 * axis] * depth + glass_shift) {
        glm::dvec2 a = in_lo, b = in_hi;
        a[axis] = -2.0 * half[axis] - in_hi[axis];
        b[axis] = -2.0 * half[axis] - in_lo[axis];
        moved_back(a, b);
      }
    }
  }
  // Out through a wall: surface points within the rays' travel towards
  // that wall, spread along it by their travel there and, past the glass,
  // by k_out per unit height (as PlateLookupRect bounds it).
  for (int axis = 0; axis < 2; ++axis) {
    const int other = 1 - axis;
    for (const double side : {-1.0, 1.0}) {
      const double wall = side * half[axis];
      if (side * (side > 0 ? hi[axis] : lo[axis]) <= half[axis]) continue;
      const double toward = travel[2 * axis + (side > 0 ? 1 : 0)] * depth;
      Box2 box;
      box.lo[axis] = side > 0 ? wall - toward - glass_shift : wall;
      box.hi[axis] = side > 0 ? wall : wall + toward + glass_shift;
      box.lo[other] =
          lo[other] - (travel[2 * other + 1] + k_out) * depth - glass_shift;
      box.hi[other] =
          hi[other] + (travel[2 * other] + k_out) * depth + glass_shift;
      out->push_back(box);
    }
  }
}

}  // namespace

glm::ivec4 ObstacleLookupRect(const FrameState& f) {
  const SceneInputs& scene = *f.scene;
  if (scene.obstacles.empty()) return {0, 0, 0, 0};
  // The board points an obstacle hides from the camera: its bounding box's
  // corners carried along the camera's rays down to the board (z = 0). A
  // camera no higher than a corner hides the board out to the horizon.
  const glm::dvec3& eye = f.cam_in_tank;
  glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const Obstacle& o : scene.obstacles) {
    glm::dvec3 corners[8];
    ObstacleBoxCorners(o, corners);
    for (const glm::dvec3& c : corners) {
      if (!(eye.z > c.z + 1e-6)) return WholeWindow(f);
      const double s = eye.z / (eye.z - std::max(c.z, 0.0));
      const glm::dvec2 q =
          glm::dvec2(eye) + (glm::dvec2(c) - glm::dvec2(eye)) * s;
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  }
  // The lookup's filter reads a couple of pixels around it.
  lo -= 0.003;
  hi += 0.003;
  // The source boxes for rays refracted by normals up to `slope`; false
  // when a ray could run near the horizontal (no bound).
  std::vector<Box2> boxes;
  auto sources = [&](double slope) {
    boxes.clear();
    double travel[4], k_out;
    if (!RefractedTravel(f, slope, travel) ||
        !OutTravel(f, RefractedReach(f, slope), &k_out)) {
      return false;
    }
    LookupSources(f, lo, hi, travel, k_out, &boxes);
    return true;
  };
  // The surface points are in the tank.
  const glm::dvec2 half(0.5 * scene.tank.size_x, 0.5 * scene.tank.size_y);
  std::vector<glm::dvec3> q;
  auto add = [&](glm::dvec2 a, glm::dvec2 b) {
    a = glm::max(a, -half);
    b = glm::min(b, half);
    if (!(a.x <= b.x && a.y <= b.y)) return;
    for (int i = 0; i < 4; ++i)
      q.emplace_back(i & 1 ? b.x : a.x, i & 2 ? b.y : a.y, 0.0);
  };
  const HeightFieldInfo& h = f.height;
  if (h.tile_slope == nullptr) {
    if (!sources(SlopeMax(f))) return WholeWindow(f);
    for (const Box2& b : boxes) add(b.lo, b.hi);
  } else {
    // Tile by tile, with the tile's own steepest slope: calm water far from
    // the waves reaches only as far as flat water's rays. The boxes are made
    // for kLevels slopes up to the frame's steepest, each tile taking the
    // next one up (the rays' travel grows with the slope).
    constexpr int kLevels = 8;
    const double top = SlopeMax(f) + SlopeCodeStep(h);
    std::vector<Box2> level_boxes[kLevels + 1];
    for (int i = 0; i <= kLevels; ++i) {
      if (!sources(top * i / kLevels)) return WholeWindow(f);
      level_boxes[i] = boxes;
    }
    ForSlopeTiles(
        h, [&](const glm::dvec2& t0, const glm::dvec2& t1, double slope) {
          const int i = std::clamp(
              static_cast<int>(std::ceil(slope / top * kLevels - 1e-9)), 0,
              kLevels);
          for (const Box2& b : level_boxes[i])
            add(glm::max(t0, b.lo), glm::min(t1, b.hi));
        });
  }
  if (q.empty()) return {0, 0, 0, 0};
  return SurfaceNear(f, q, 0.0);
}

}  // namespace ripple::render::internal
