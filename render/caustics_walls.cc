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

void NearWallGlassMaps(const TankGeometry& tank, const glm::dvec3& l,
                       double ior, double glass_ior, int mx, int my,
                       float* gain, float* add) {
  const size_t n = static_cast<size_t>(mx) * my;
  std::fill(gain, gain + n, 1.0f);
  std::fill(add, add + n, 0.0f);
  const glm::dvec3 d = -l;  // travel direction of the light
  const glm::dvec3 t = glm::refract(d, glm::dvec3(0, 0, 1), 1.0 / ior);
  if (!(t.z < -1e-9) || !(l.z > 1e-9)) return;
  const double h[2] = {0.5 * tank.size_x, 0.5 * tank.size_y};
  // Flat water moves the light by `shift` from the surface to the floor.
  const double shift[2] = {tank.water_level * t.x / -t.z,
                           tank.water_level * t.y / -t.z};
  const double above = tank.wall_height - tank.water_level;
  // A glass slab in air at cos_i, with its internal reflections summed
  // (incoherently): R_slab = 2R / (1 + R), T_slab = (1 - R) / (1 + R).
  auto slab_r = [&](double cos_i) {
    const double r = FresnelReflectance(cos_i, 1.0, glass_ior);
    return 2.0 * r / (1.0 + r);
  };
  const double la[2] = {l.x, l.y};
  // Transmittance of the glass above the water on the light arriving at
  // surface point s from above: a wall facing the light (at side * h) is
  // crossed when the ray towards the light meets it below its top.
  auto transmitted = [&](const double s[2]) {
    double g = 1.0;
    for (int a = 0; a < 2; ++a) {
      if (std::abs(la[a]) < 1e-9) continue;
      const double side = la[a] > 0 ? 1.0 : -1.0;
      const double u = (side * h[a] - s[a]) / la[a];
      if (u >= 0 && u * l.z < above &&
          std::abs(s[1 - a] + u * la[1 - a]) <= h[1 - a])
        g *= 1.0 - slab_r(std::abs(la[a]));
    }
    return g;
  };
  // The light reflected onto surface point s by the wall facing away along
  // axis a (at -side * h), above the water: it arrives mirrored in a.
  auto reflected = [&](const double s[2], int a) {
    if (std::abs(la[a]) < 1e-9) return 0.0;
    const double side = la[a] > 0 ? 1.0 : -1.0;
    const double v = (side * h[a] + s[a]) / la[a];
    const bool hits = v >= 0 && v * l.z < above &&
                      std::abs(s[1 - a] + v * la[1 - a]) <= h[1 - a];
    return hits ? slab_r(std::abs(la[a])) : 0.0;
  };
  const double cell[2] = {tank.size_x / mx, tank.size_y / my};
  constexpr int kSub = 4;
  // Only texels near a wall can differ: within the light's run above the
  // water plus the shift of any wall.
  const double reach_x = above * std::abs(l.x) / l.z + std::abs(shift[0]);
  const double reach_y = above * std::abs(l.y) / l.z + std::abs(shift[1]);
  for (int j = 0; j < my; ++j) {
    for (int i = 0; i < mx; ++i) {
      const double x0 = -h[0] + i * cell[0], y0 = -h[1] + j * cell[1];
      const bool near = x0 < -h[0] + reach_x + cell[0] ||
                        x0 + cell[0] > h[0] - reach_x - cell[0] ||
                        y0 < -h[1] + reach_y + cell[1] ||
                        y0 + cell[1] > h[1] - reach_y - cell[1];
      if (!near) continue;
      double g_sum = 0, a_sum = 0;
      for (int sj = 0; sj < kSub; ++sj) {
        for (int si = 0; si < kSub; ++si) {
          const double f[2] = {x0 + (si + 0.5) * cell[0] / kSub,
                               y0 + (sj + 0.5) * cell[1] / kSub};
          const double sp[2] = {f[0] - shift[0], f[1] - shift[1]};
          g_sum += transmitted(sp);
          for (int a = 0; a < 2; ++a) {
            // Light reflected by the wall facing away: mirrored in a, so it
            // reaches f from the surface point shifted the other way.
            double sr[2] = {sp[0], sp[1]};
            sr[a] = f[a] + shift[a];
            if (std::abs(sr[0]) < h[0] && std::abs(sr[1]) < h[1])
              a_sum += reflected(sr, a);
            // The light that would land beyond the wall facing away (its
            // mirror image of f) and came through the surface inside: the
            // wall below the water mirrors it back onto f.
            if (std::abs(shift[a]) < 1e-12) continue;
            const double wall = shift[a] > 0 ? h[a] : -h[a];
            double m[2] = {f[0], f[1]};
            m[a] = 2.0 * wall - f[a];
            const double sm[2] = {m[0] - shift[0], m[1] - shift[1]};
            if (std::abs(sm[0]) < h[0] && std::abs(sm[1]) < h[1]) {
              const double cos_w = std::abs(a == 0 ? t.x : t.y);
              a_sum +=
                  SideWallReflectance(cos_w, ior, glass_ior) * transmitted(sm);
            }
          }
        }
      }
      const size_t at = static_cast<size_t>(j) * mx + i;
      gain[at] = static_cast<float>(g_sum / (kSub * kSub));
      add[at] = static_cast<float>(a_sum / (kSub * kSub));
    }
  }
}

}  // namespace ripple::render::caustics_internal
