// The parts of the caustics map that need no surface mesh: flat water's
// lit area, and the light that enters through the glass side walls.
#include <algorithm>
#include <cmath>

#include "render/caustics_kernels.h"
#include "render/optics.h"

namespace ripple::render::caustics_internal {
namespace {

// Length of [a0, a1] inside [b0, b1].
double Overlap(double a0, double a1, double b0, double b1) {
  return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
}

}  // namespace

void FlatSurfaceMap(const TankGeometry& tank, const glm::dvec3& l, double ior,
                    int mx, int my, float* map) {
  // Refracted light through the flat surface shifts the lit rectangle by
  // level * t.xy / |t.z| (away from the light).
  const glm::dvec3 t = glm::refract(-l, glm::dvec3(0, 0, 1), 1.0 / ior);
  const double sx = tank.water_level * t.x / -t.z;
  const double sy = tank.water_level * t.y / -t.z;
  const double hx = 0.5 * tank.size_x, hy = 0.5 * tank.size_y;
  const double tx = tank.size_x / mx, ty = tank.size_y / my;
  std::vector<double> fx(mx);
  for (int a = 0; a < mx; ++a) {
    const double x0 = -hx + a * tx;
    fx[a] = Overlap(x0, x0 + tx, -hx + sx, hx + sx) / tx;
  }
  for (int b = 0; b < my; ++b) {
    const double y0 = -hy + b * ty;
    const double fy = Overlap(y0, y0 + ty, -hy + sy, hy + sy) / ty;
    float* row = map + static_cast<size_t>(b) * mx;
    for (int a = 0; a < mx; ++a) row[a] = static_cast<float>(fx[a] * fy);
  }
}

double AddWallLight(const TankGeometry& tank, const glm::dvec3& l, double ior,
                    double glass_ior, double attenuation_per_m, int mx, int my,
                    float* map) {
  const glm::dvec3 d = -l;  // travel direction of the light
  const glm::dvec3 t_flat = glm::refract(d, glm::dvec3(0, 0, 1), 1.0 / ior);
  const double len_flat = tank.water_level / -t_flat.z;
  const double t_surface = 1.0 - FresnelReflectance(l.z, 1.0, ior);
  const double hx = 0.5 * tank.size_x, hy = 0.5 * tank.size_y;
  const double tx = tank.size_x / mx, ty = tank.size_y / my;
  const double texel_area = tx * ty;
  double flux = 0;
  // axis 0: the x walls, 1: the y walls. A wall is lit when the light comes
  // from its outside.
  for (int axis = 0; axis < 2; ++axis) {
    const double la = axis == 0 ? l.x : l.y;
    if (std::abs(la) < 1e-9) continue;
    const double side = la > 0 ? 1.0 : -1.0;  // the wall at side * half size
    const glm::dvec3 normal =
        axis == 0 ? glm::dvec3(side, 0, 0) : glm::dvec3(0, side, 0);
    const double cos_i = std::abs(la);
    // A thin slab refracts as air to water; its two faces transmit.
    const glm::dvec3 t = glm::refract(d, normal, 1.0 / ior);
    const double sin2_g = (1.0 - cos_i * cos_i) / (glass_ior * glass_ior);
    const double cos_g = std::sqrt(std::max(0.0, 1.0 - sin2_g));
    const double t_wall = (1.0 - FresnelReflectance(cos_i, 1.0, glass_ior)) *
                          (1.0 - FresnelReflectance(cos_g, glass_ior, ior));
    const double ta = axis == 0 ? t.x : t.y;  // towards the inside, < 0 side
    if (!(std::abs(ta) > 1e-9) || !(t.z < -1e-9)) continue;
    // Floor irradiance through the wall over that through flat water: a wall
    // patch dz x dw takes cos_i of the beam and spreads it over
    // dz |t_a / t_z| x dw of floor.
    const double ratio =
        (t_wall / t_surface) * cos_i * (-t.z) / (std::abs(ta) * l.z);
    // Floor points up to level * |t_a / t_z| from the wall can be reached.
    const double reach = tank.water_level * std::abs(ta) / -t.z;
    const double wall_pos = side * (axis == 0 ? hx : hy);
    constexpr int kSub = 4;
    for (int b = 0; b < my; ++b) {
      for (int a = 0; a < mx; ++a) {
        const double x0 = -hx + a * tx, y0 = -hy + b * ty;
        const double along = axis == 0 ? x0 : y0;
        const double cell = axis == 0 ? tx : ty;
        // Distance of the texel from the wall: skip those out of reach.
        const double dist =
            side > 0 ? wall_pos - (along + cell) : along - wall_pos;
        if (dist > reach) continue;
        double sum = 0;
        for (int sj = 0; sj < kSub; ++sj) {
          for (int si = 0; si < kSub; ++si) {
            const glm::dvec3 f(x0 + (si + 0.5) * tx / kSub,
                               y0 + (sj + 0.5) * ty / kSub, 0.0);
            // Back along the ray to the wall's plane.
            const double s = (wall_pos - (axis == 0 ? f.x : f.y)) / -ta;
            if (s < 0) continue;
            const glm::dvec3 e = f - s * t;
            const double across = axis == 0 ? e.y : e.x;
            const double half_across = axis == 0 ? hy : hx;
            if (e.z > tank.water_level || std::abs(across) > half_across) {
              continue;
            }
            sum += std::exp(-attenuation_per_m * (s - len_flat));
          }
        }
        const double add = ratio * sum / (kSub * kSub);
        map[static_cast<size_t>(b) * mx + a] += static_cast<float>(add);
        flux += add * texel_area * l.z;
      }
    }
  }
  return flux;
}

}  // namespace ripple::render::caustics_internal
