#include "render/water_regions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace ripple::render::internal {
namespace {

constexpr double kWaveRange_m = 0.01;  // the surface within rest +- 1 cm

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

// Window rectangle of the surface points (z at the rest level's lowest and
// highest) within `reach` metres horizontally of the tank points `q`.
glm::ivec4 SurfaceNear(const FrameState& f, const std::vector<glm::dvec3>& q,
                       double reach) {
  const double level = f.scene->tank.water_level;
  std::vector<glm::dvec3> pts;
  pts.reserve(q.size() * 8);
  for (const glm::dvec3& p : q) {
    for (const double z : {level - kWaveRange_m, level + kWaveRange_m}) {
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

// The largest horizontal travel per unit depth of a ray refracted into the
// water: the camera's rays to the tank's corners at the rest level (the
// steepest incidence is at the farthest corner), the normal tilted by up to
// `slope` in 16 directions, and 10 % over the samples; infinity when a ray
// could run near the horizontal.
double RefractedReach(const FrameState& f, double slope) {
  const TankGeometry& t = f.scene->tank;
  const double eta = 1.0 / f.optics->ior;
  double k = 0;
  for (int c = 0; c < 4; ++c) {
    const glm::dvec3 corner((c & 1 ? 0.5 : -0.5) * t.size_x,
                            (c & 2 ? 0.5 : -0.5) * t.size_y, t.water_level);
    const glm::dvec3 v = glm::normalize(corner - f.cam_in_tank);
    for (int s = 0; s <= 2; ++s) {
      const double m = slope * s / 2.0;
      for (int a = 0; a < (s == 0 ? 1 : 16); ++a) {
        const double phi = a * (2.0 * M_PI / 16.0);
        const glm::dvec3 n = glm::normalize(
            glm::dvec3(-m * std::cos(phi), -m * std::sin(phi), 1));
        const glm::dvec3 r = glm::refract(v, n, eta);
        if (!(r.z < -0.1)) return std::numeric_limits<double>::infinity();
        k = std::max(k, std::hypot(r.x, r.y) / -r.z);
      }
    }
  }
  return 1.1 * k;
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
  const double level = f.scene->tank.water_level;
  const double top = level + kWaveRange_m;
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
  const double level = f.scene->tank.water_level;
  // The lookup point (the surface point moved by the slope) on either
  // surface height, then the surface points within reach of it.
  std::vector<glm::dvec3> q;
  if (!CornersOnPlanes(f, mirror_window, 0.0,
                       {level - kWaveRange_m, level + kWaveRange_m}, &q)) {
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
  // The slopes' 8-bit code rounds by up to half a step.
  const double code_step =
      0.5 * std::hypot(h.decode_scale.y, h.decode_scale.z) / 255.0;
  const glm::dvec2 origin = -0.5 * glm::dvec2(h.extent);
  constexpr double kFar = 1e3;  // metres: "unbounded" for border tiles
  std::vector<glm::dvec3> pts;
  for (int j = 0; j < h.tiles_y; ++j) {
    for (int i = 0; i < h.tiles_x; ++i) {
      const double slope = h.tile_slope[static_cast<size_t>(j) * h.tiles_x + i];
      const double reach = 2.0 * kMirrorDepth_m * (slope + code_step) + 0.001;
      glm::dvec2 t0 = origin + glm::dvec2(i, j) * double(h.tile_m);
      glm::dvec2 t1 = t0 + glm::dvec2(h.tile_m);
      if (i == 0) t0.x = -kFar;
      if (j == 0) t0.y = -kFar;
      if (i == h.tiles_x - 1) t1.x = kFar;
      if (j == h.tiles_y - 1) t1.y = kFar;
      const glm::dvec2 a = glm::max(t0, lo - reach);
      const glm::dvec2 b = glm::min(t1, hi + reach);
      if (!(a.x <= b.x && a.y <= b.y)) continue;
      for (const double z : {level - kWaveRange_m, level + kWaveRange_m}) {
        for (int c = 0; c < 4; ++c)
          pts.emplace_back(c & 1 ? b.x : a.x, c & 2 ? b.y : a.y, z);
      }
    }
  }
  if (pts.empty()) return {0, 0, 0, 0};
  return PointsRect(f.clip_from_tank, pts.data(), static_cast<int>(pts.size()),
                    2, f.k->width, f.k->height);
}

glm::ivec4 PlateLookupRect(const FrameState& f,
                           const glm::ivec4& image_window) {
  if (Empty(image_window)) return {0, 0, 0, 0};
  // Image pixels x .. x + w - 1 are window positions x .. x + w; one more
  // pixel each way for the mask's filtering.
  std::vector<glm::dvec3> q;
  if (!CornersOnPlanes(f, image_window, 1.0, {0.0}, &q)) return WholeWindow(f);
  const double depth = f.scene->tank.water_level + kWaveRange_m;
  const double k = RefractedReach(f, SlopeMax(f));
  // Out through a vertical wall the ray's vertical component grows by the
  // index: |d_z| = n / sqrt(1 + k^2) at the shallowest.
  const double out_z = std::min(1.0, f.optics->ior / std::sqrt(1.0 + k * k));
  if (!std::isfinite(k) || out_z < 0.1) return WholeWindow(f);
  const double k_out = std::sqrt(1.0 - out_z * out_z) / out_z;
  // A ray the glass totally reflects also moves along the wall inside it,
  // by 2 d tan(theta_g) at most, and theta_g < asin(n_water / n_glass).
  const double sin_g = std::min(f.optics->ior / f.optics->glass_ior, 0.999f);
  const double glass_shift = 2.0 * f.optics->glass_thickness_m * sin_g /
                             std::sqrt(1.0 - sin_g * sin_g);
  return SurfaceNear(f, q, (k + k_out) * depth + glass_shift + 0.001);
}

}  // namespace ripple::render::internal
