#include "sim/obstacle_cover.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace ripple::sim {

void RasterizeObstacle(const GridSpec& grid, const Obstacle& o,
                       ObstacleCover* state) {
  const int nx = grid.nx, ny = grid.ny;
  const double d = grid.cell_m, level = grid.rest_level_m;
  state->i0 = state->i1 = state->j0 = state->j1 = 0;
  state->covers.clear();
  // Tank-frame bounds of the shape from its 8 local corners.
  const auto local = o.LocalBounds();
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (int corner = 0; corner < 8; ++corner) {
    const std::array<double, 3> p = {local[corner & 1][0],
                                     local[(corner >> 1) & 1][1],
                                     local[(corner >> 2) & 1][2]};
    const auto q = o.tank_from_obstacle.Apply(p);
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], q[a]);
      hi[a] = std::max(hi[a], q[a]);
    }
  }
  if (!(lo[2] <= level && hi[2] >= level)) return;  // misses the surface
  auto index_range = [&](double a, double b, int n, int* i0, int* i1) {
    // Cells whose centre (i + 0.5 - n/2) * d lies in [a, b].
    const double f0 = std::ceil(a / d + 0.5 * n - 0.5);
    const double f1 = std::floor(b / d + 0.5 * n - 0.5);
    *i0 = static_cast<int>(std::clamp(f0, 0.0, double(n)));
    *i1 = static_cast<int>(std::clamp(f1 + 1, 0.0, double(n)));
  };
  index_range(lo[0], hi[0], nx, &state->i0, &state->i1);
  index_range(lo[1], hi[1], ny, &state->j0, &state->j1);
  if (state->i0 >= state->i1 || state->j0 >= state->j1) {
    state->i0 = state->i1 = state->j0 = state->j1 = 0;
    return;
  }
  const RigidTransform obstacle_from_tank = o.tank_from_obstacle.Inverse();
  const int w = state->i1 - state->i0;
  state->covers.assign(static_cast<size_t>(w) * (state->j1 - state->j0), 0);
  for (int j = state->j0; j < state->j1; ++j) {
    for (int i = state->i0; i < state->i1; ++i) {
      const std::array<double, 3> p_in_tank = {(i + 0.5 - 0.5 * nx) * d,
                                               (j + 0.5 - 0.5 * ny) * d, level};
      state->covers[static_cast<size_t>(j - state->j0) * w + (i - state->i0)] =
          o.ContainsInObstacle(obstacle_from_tank.Apply(p_in_tank));
    }
  }
}

}  // namespace ripple::sim
