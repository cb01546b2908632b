// The parts of the caustics map that need no surface mesh: flat water's
// lit area, and what the glass walls change near them.
#include <algorithm>
#include <cmath>

#include "render/caustics_kernels.h"
#include "render/optics.h"
#include "render/tank_paths.h"

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

double NearWallGlassMaps(const TankGeometry& tank, double glass_thickness_m,
                         const glm::dvec3& l, double ior, double glass_ior,
                         double attenuation_per_m, int mx, int my,
                         int paths_per_axis, float* gain, float* add) {
  const size_t n = static_cast<size_t>(mx) * my;
  std::fill(gain, gain + n, 1.0f);
  std::fill(add, add + n, 0.0f);
  double flux = 0;
  const glm::dvec3 d = -l;  // travel direction of the light
  const glm::dvec3 t = glm::refract(d, glm::dvec3(0, 0, 1), 1.0 / ior);
  if (!(t.z < -1e-9) || !(l.z > 1e-9)) return flux;
  const internal::PathTank tk = internal::MakePathTank(
      tank, glass_thickness_m, ior, glass_ior, glm::dvec3(attenuation_per_m));
  // Flat open water's light on the floor, per unit of the light's
  // irradiance on a plane facing it: l.z T_surface exp(-sigma level / |t_z|).
  const double open = (1.0 - FresnelReflectance(l.z, 1.0, ior)) *
                      std::exp(-attenuation_per_m * tk.W / -t.z);
  const double h[2] = {tk.a, tk.b};
  const double cell[2] = {tank.size_x / mx, tank.size_y / my};
  // How far from a wall the glass can change the surface's light, per axis:
  // the light's run over the wall above the water, the refracted light's
  // over the water's depth, the glass and two texels; or the run over the
  // water's depth of the light that crossed the wall facing away above the
  // water and came back in below the water line after its outer face's
  // reflection. That light leaves the inner face as if refracted straight
  // from the air into the water through the wall's plane (the slab's faces
  // are parallel): along the wall's normal n_w sqrt(1 - (1 - l_a^2) / n_w^2),
  // down l.z, so it runs sqrt(n_w^2 - 1 + l_a^2) / l.z per unit of depth,
  // about one depth under a light 23 degrees off the vertical.
  const double la[2] = {l.x, l.y};
  double reach[2];
  for (int a = 0; a < 2; ++a) {
    const double refracted = (tk.H - tk.W) * std::abs(la[a]) / l.z +
                             tk.W * std::abs(a == 0 ? t.x : t.y) / -t.z;
    const double back_in =
        tk.W * std::sqrt(ior * ior - 1.0 + la[a] * la[a]) / l.z;
    reach[a] = std::max(refracted, back_in) + glass_thickness_m + 2.0 * cell[a];
  }
  auto near_texel = [&](int i, int j, double grow) {
    const double x = -h[0] + (i + 0.5) * cell[0];
    const double y = -h[1] + (j + 0.5) * cell[1];
    return h[0] - std::abs(x) < reach[0] + grow * cell[0] ||
           h[1] - std::abs(y) < reach[1] + grow * cell[1];
  };
  // Per texel, in units of one path: the light by how it came into the
  // water (PathEntry), and `flat`, where the same paths would land without
  // the glass. Splatted bilinearly at the texel centres, so that a lattice
  // of k x k paths per texel gives exactly k^2 wherever it lands evenly.
  std::vector<double> surface(n, 0.0), mirrored(n, 0.0), flat(n, 0.0);
  auto splat = [&](std::vector<double>* map, double x, double y, double w) {
    const double u = (x + h[0]) / cell[0] - 0.5, v = (y + h[1]) / cell[1] - 0.5;
    const int i0 = static_cast<int>(std::floor(u));
    const int j0 = static_cast<int>(std::floor(v));
    const double fu = u - i0, fv = v - j0;
    for (int dj = 0; dj < 2; ++dj) {
      for (int di = 0; di < 2; ++di) {
        // The floor's edge texels keep what lands beyond their centres.
        const int i = std::clamp(i0 + di, 0, mx - 1);
        const int j = std::clamp(j0 + dj, 0, my - 1);
        (*map)[static_cast<size_t>(j) * mx + i] +=
            w * (di ? fu : 1 - fu) * (dj ? fv : 1 - fv);
      }
    }
  };
  auto end = [&](internal::PathEnd kind, const glm::dvec3& p,
                 const glm::dvec3& w, internal::PathEntry entry) {
    if (kind != internal::PathEnd::kFloor) return;
    switch (entry) {
      case internal::PathEntry::kSurface:
        splat(&surface, p.x, p.y, w.x);
        break;
      case internal::PathEntry::kSurfaceThenGlass:
      case internal::PathEntry::kWallIndirect:
        splat(&mirrored, p.x, p.y, w.x);
        break;
      case internal::PathEntry::kWall:  // AddWallLight's, analytically
      case internal::PathEntry::kNone:
      case internal::PathEntry::kGlassIndirect:
        break;
    }
  };
  // Paths aimed at a lattice of k x k points per texel on the board's plane
  // (where each would land without the tank), over the tank's footprint and
  // the light's run over the walls' height beyond it. A path that meets no
  // glass and lands two texels or more beyond the walls' reach adds the
  // same to `surface` and `flat` of texels that are not written: such paths
  // are not traced.
  const int k = std::max(1, paths_per_axis);
  const double step[2] = {cell[0] / k, cell[1] / k};
  const double rise = (tk.H + 0.001) / l.z;
  // The lattice: the points whose line up towards the light passes over
  // the outer footprint below the walls' top, from the footprint to its
  // shadow's far end.
  int lo[2], hi[2];
  for (int a = 0; a < 2; ++a) {
    const double outer = h[a] + glass_thickness_m;
    const double run = tk.H * la[a] / l.z;
    lo[a] =
        static_cast<int>(std::floor(std::min(-outer, -outer - run) / step[a]));
    hi[a] = static_cast<int>(std::ceil(std::max(outer, outer - run) / step[a]));
  }
  const double shift[2] = {tk.W * t.x / -t.z, tk.W * t.y / -t.z};
  for (int jj = lo[1]; jj < hi[1]; ++jj) {
    for (int ii = lo[0]; ii < hi[0]; ++ii) {
      const glm::dvec3 q((ii + 0.5) * step[0], (jj + 0.5) * step[1], 0.0);
      // Heights at which the line is over the outer footprint: none below
      // the walls' top, and the tank is not in its way.
      double z0 = 0.0, z1 = tk.H;
      for (int a = 0; a < 2; ++a) {
        const double outer = h[a] + glass_thickness_m;
        if (std::abs(la[a]) < 1e-12) {
          if (std::abs(q[a]) >= outer) z1 = -1.0;
          continue;
        }
        double za = (-outer - q[a]) * l.z / la[a];
        double zb = (outer - q[a]) * l.z / la[a];
        if (za > zb) std::swap(za, zb);
        z0 = std::max(z0, za);
        z1 = std::min(z1, zb);
      }
      if (!(z0 < z1)) continue;
      // Without the glass: the light crosses the walls' top height at
      // `top`, the surface at `s` and lands at `f`.
      const double top[2] = {q.x + tk.H * l.x / l.z, q.y + tk.H * l.y / l.z};
      const double s[2] = {q.x + tk.W * l.x / l.z, q.y + tk.W * l.y / l.z};
      const double f[2] = {s[0] + shift[0], s[1] + shift[1]};
      bool plain = true;
      for (int a = 0; a < 2; ++a) {
        plain = plain && std::abs(top[a]) < h[a] && std::abs(s[a]) < h[a] &&
                std::abs(f[a]) < h[a];
      }
      if (plain) {
        const int i = static_cast<int>(std::floor((f[0] + h[0]) / cell[0]));
        const int j = static_cast<int>(std::floor((f[1] + h[1]) / cell[1]));
        if (!near_texel(i, j, 2.0)) continue;
      }
      // A path into a wall's outer face below the water goes on into the
      // water below it (AddWallLight's light) or back out: not traced.
      bool into_wall = false;
      for (int a = 0; a < 2 && !into_wall; ++a) {
        if (std::abs(la[a]) < 1e-12) continue;
        const double face = std::copysign(h[a] + glass_thickness_m, la[a]);
        const double z = (face - q[a]) * l.z / la[a];
        const double across = q[1 - a] + z * la[1 - a] / l.z;
        into_wall = z >= 0 && z < tk.W &&
                    std::abs(across) < h[1 - a] + glass_thickness_m;
      }
      if (into_wall) continue;
      if (std::abs(s[0]) < h[0] && std::abs(s[1]) < h[1] &&
          std::abs(f[0]) < h[0] && std::abs(f[1]) < h[1])
        splat(&flat, f[0], f[1], 1.0);
      internal::TracePath(tk, q + rise * l, d,
                          internal::PathMedium::kAirOutside, glm::dvec3(1.0),
                          end);
    }
  }
  // Relative to flat open water: a path carries the light of step_x step_y
  // of the board's plane, l.z times it in the open.
  const double per_path = 1.0 / (k * k * open);
  const double texel_flux = cell[0] * cell[1] * l.z;
  const double full = k * k;
  for (int j = 0; j < my; ++j) {
    for (int i = 0; i < mx; ++i) {
      if (!near_texel(i, j, 0.0)) continue;
      const size_t at = static_cast<size_t>(j) * mx + i;
      const double sf = surface[at] * per_path;
      const double mf = mirrored[at] * per_path;
      // The surface's own light carries the waves' caustics: it stays a
      // gain on the surface's map where the glass-free paths fill a fair
      // share of the texel; elsewhere it is added as it lands under flat
      // water.
      if (flat[at] > 0.25 * full) {
        gain[at] = static_cast<float>(sf / (flat[at] / full));
        add[at] = static_cast<float>(mf);
      } else {
        gain[at] = 0.0f;
        add[at] = static_cast<float>(sf + mf);
      }
      flux += (sf + mf - flat[at] / full) * texel_flux;
    }
  }
  return flux;
}

}  // namespace ripple::render::caustics_internal
