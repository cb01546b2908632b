#include "render/board_light.h"

#include <algorithm>
#include <cmath>

#include "render/renderer.h"
#include "render/tank_paths.h"

namespace ripple::render::internal {
namespace {

glm::dvec3 TexelCentre(const BoardLightMap& m, int i, int j) {
  return {m.origin.x + (i + 0.5) * m.texel, m.origin.y + (j + 0.5) * m.texel,
          0.0};
}

}  // namespace

bool BoardLightMap::InFootprint(double x, double y) const {
  return std::abs(x) < outer_x && std::abs(y) < outer_y;
}

BoardTexel BoardLightMap::Texel(int i, int j, const WaterOptics& optics,
                                float under_glass_light) const {
  const glm::dvec3 p = TexelCentre(*this, i, j);
  if (InFootprint(p.x, p.y)) {
    // Out to the nearest side of the footprint, and one texel beyond it.
    const double to_x = outer_x - std::abs(p.x), to_y = outer_y - std::abs(p.y);
    const int steps = static_cast<int>(std::ceil(std::min(to_x, to_y) / texel));
    if (to_x < to_y) {
      i += p.x < 0 ? -steps : steps;
    } else {
      j += p.y < 0 ? -steps : steps;
    }
    i = std::clamp(i, 0, nx - 1);
    j = std::clamp(j, 0, ny - 1);
  }
  const int k = j * nx + i;
  // The sky's view, bilinear between its texel centres.
  const glm::dvec3 c = TexelCentre(*this, i, j);
  const double u =
      std::clamp((c.x - view.origin.x) / view.texel - 0.5, 0.0, view.nx - 1.0);
  const double v =
      std::clamp((c.y - view.origin.y) / view.texel - 0.5, 0.0, view.ny - 1.0);
  const int i0 = std::min(static_cast<int>(u), view.nx - 2);
  const int j0 = std::min(static_cast<int>(v), view.ny - 2);
  const float fu = static_cast<float>(u - i0), fv = static_cast<float>(v - j0);
  glm::vec3 sky(0.0f);
  BoardTexel t;
  for (int dj = 0; dj < 2; ++dj) {
    for (int di = 0; di < 2; ++di) {
      const float w = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv);
      const size_t q = static_cast<size_t>(j0 + dj) * view.nx + i0 + di;
      sky += w * view.sky[q];
      t.diffuse +=
          w * (view.board[q] + view.under_glass[q] * under_glass_light);
      t.floor += w * view.floor[q];
    }
  }
  const float a = optics.ambient_share;
  t.light =
      a * optics.sky_tint * sky + (1.0f - a) * optics.sun_tint * direct[k];
  return t;
}

glm::vec3 BoardLightMap::LightAt(double x, double y, const WaterOptics& optics,
                                 float paper) const {
  const int i = static_cast<int>(std::floor((x - origin.x) / texel));
  const int j = static_cast<int>(std::floor((y - origin.y) / texel));
  if (i < 0 || j < 0 || i >= nx || j >= ny) return glm::vec3(1.0f);
  const BoardTexel t = Texel(i, j, optics, 1.0f);
  return {t.Factor(0, paper, 1.0f), t.Factor(1, paper, 1.0f),
          t.Factor(2, paper, 1.0f)};
}

BoardLightMap BoardLightLayout(const TankGeometry& tank,
                               const WaterOptics& optics,
                               const BoardLightOptions& options) {
  BoardLightMap m;
  m.outer_x = 0.5 * tank.size_x + optics.glass_thickness_m;
  m.outer_y = 0.5 * tank.size_y + optics.glass_thickness_m;
  const double reach = 2.0 * tank.wall_height;
  m.texel = options.texel_m;
  m.nx = static_cast<int>(std::ceil(2.0 * (m.outer_x + reach) / m.texel));
  m.ny = static_cast<int>(std::ceil(2.0 * (m.outer_y + reach) / m.texel));
  m.origin = {-0.5 * m.nx * m.texel, -0.5 * m.ny * m.texel};
  return m;
}

void ComputeBoardSkyView(const TankGeometry& tank, const WaterOptics& optics,
                         const BoardLightOptions& options, BoardLightMap* map) {
  const PathTank t = MakePathTank(tank, optics);
  // An even side, so the set is its own mirror image in x and in y.
  const int side =
      std::max(2, 2 * (static_cast<int>(std::sqrt(options.sky_rays)) / 2));
  const int rays = side * side;
  const std::vector<glm::dvec3> dirs = CosineDirections(side);
  BoardSkyView& view = map->view;
  const int step = std::max(1, options.sky_texels);
  view.texel = map->texel * step;
  // An even count each way, centred, covering the map and a texel beyond.
  view.nx = 2 * (static_cast<int>(std::ceil(-map->origin.x / view.texel)) + 1);
  view.ny = 2 * (static_cast<int>(std::ceil(-map->origin.y / view.texel)) + 1);
  view.origin = {-0.5 * view.nx * view.texel, -0.5 * view.ny * view.texel};
  const size_t n = static_cast<size_t>(view.nx) * view.ny;
  view.sky.assign(n, glm::vec3(0.0f));
  view.board.assign(n, 0.0f);
  view.floor.assign(n, 0.0f);
  view.under_glass.assign(n, 0.0f);
  // Radiance over the far end's, across the interfaces on the way: a
  // diffuse point in glass is seen from the air at 1 / n^2 of its radiance
  // there (radiance / n^2 is invariant). The floor's share is kept in
  // units of its radiance as the air sees it (BoardLightMap::Texel).
  const double glass_scale = 1.0 / (t.n_glass * t.n_glass);
  // The tank and the direction set are symmetric under x -> -x and
  // y -> -y: one quadrant is traced, the others are its mirror images.
  for (int j = view.ny / 2; j < view.ny; ++j) {
    for (int i = view.nx / 2; i < view.nx; ++i) {
      glm::dvec3 p(view.origin.x + (i + 0.5) * view.texel,
                   view.origin.y + (j + 0.5) * view.texel, 0.0);
      if (map->InFootprint(p.x, p.y)) {
        // Out to the nearest side, 0.1 mm beyond it.
        const double to_x = map->outer_x - std::abs(p.x);
        const double to_y = map->outer_y - std::abs(p.y);
        if (to_x < to_y) {
          p.x = std::copysign(map->outer_x + 1e-4, p.x);
        } else {
          p.y = std::copysign(map->outer_y + 1e-4, p.y);
        }
      }
      PathEndSums sums;
      for (const glm::dvec3& d : dirs) {
        TracePath(t, p, d, PathMedium::kAirOutside, glm::dvec3(1.0), sums);
      }
      for (const int jj : {j, view.ny - 1 - j}) {
        for (const int ii : {i, view.nx - 1 - i}) {
          const size_t k = static_cast<size_t>(jj) * view.nx + ii;
          view.sky[k] = glm::vec3(sums.sky / double(rays));
          view.board[k] = static_cast<float>(sums.board / rays);
          view.floor[k] = static_cast<float>(sums.floor / rays);
          view.under_glass[k] =
              static_cast<float>(sums.under_glass * glass_scale / rays);
        }
      }
    }
  }
}

void ComputeBoardDirectLight(const TankGeometry& tank,
                             const WaterOptics& optics, const glm::dvec3& light,
                             const BoardLightOptions& options,
                             BoardLightMap* map) {
  const PathTank t = MakePathTank(tank, optics);
  const glm::dvec3 l = glm::normalize(light);
  const size_t n = static_cast<size_t>(map->nx) * map->ny;
  // The light deposited, and the open board's share of each texel: the
  // splat weight of the lattice points outside the footprint (k^2 away
  // from it; less on the texels its edge cuts, whose light is taken over
  // the part of the board they hold).
  std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
  std::vector<double> open(n, 0.0);
  const double tau = map->texel;
  auto splat = [&](const glm::dvec3& p, const glm::dvec3& w, bool board) {
    const double u = (p.x - map->origin.x) / tau - 0.5;
    const double v = (p.y - map->origin.y) / tau - 0.5;
    const int i0 = static_cast<int>(std::floor(u));
    const int j0 = static_cast<int>(std::floor(v));
    const double fu = u - i0, fv = v - j0;
    for (int dj = 0; dj < 2; ++dj) {
      for (int di = 0; di < 2; ++di) {
        const int i = i0 + di, j = j0 + dj;
        if (i < 0 || j < 0 || i >= map->nx || j >= map->ny) continue;
        const double wt = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv);
        const size_t idx = static_cast<size_t>(j) * map->nx + i;
        if (board) {
          open[idx] += wt;
        } else {
          sum[idx] += wt * w;
        }
      }
    }
  };
  auto end = [&](PathEnd kind, const glm::dvec3& p, const glm::dvec3& w,
                 PathEntry) {
    if (kind == PathEnd::kBoard && !map->InFootprint(p.x, p.y))
      splat(p, w, false);
  };
  // A lattice of k x k points per texel, offset so that its bilinear splat
  // on the open board is uniform (one texel beyond the map on each side, so
  // its edge texels too).
  const int k = std::max(1, options.light_paths_per_axis);
  const double step = tau / k;
  const double rise = (t.H + 0.001) / std::max(l.z, 1e-3);
  for (int j = -k; j < (map->ny + 1) * k; ++j) {
    for (int i = -k; i < (map->nx + 1) * k; ++i) {
      const glm::dvec3 q(map->origin.x + (i + 0.5) * step,
                         map->origin.y + (j + 0.5) * step, 0.0);
      if (!map->InFootprint(q.x, q.y)) splat(q, glm::dvec3(1.0), true);
      TracePath(t, q + rise * l, -l, PathMedium::kAirOutside, glm::dvec3(1.0),
                end);
    }
  }
  map->direct.assign(n, glm::vec3(0.0f));
  for (int j = 0; j < map->ny; ++j) {
    for (int i = 0; i < map->nx; ++i) {
      const glm::dvec3 p = TexelCentre(*map, i, j);
      const size_t idx = static_cast<size_t>(j) * map->nx + i;
      if (!map->InFootprint(p.x, p.y) && open[idx] > 0.0) {
        map->direct[idx] = glm::vec3(sum[idx] / open[idx]);
      }
    }
  }
}

}  // namespace ripple::render::internal

namespace ripple::render {

double TankShadowReach(const TankGeometry& tank, const WaterOptics& optics) {
  return optics.glass_thickness_m + 2.0 * tank.wall_height;
}

}  // namespace ripple::render
