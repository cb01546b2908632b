// The grid cells an obstacle blocks: a cell is blocked when the point on the
// rest surface above its centre lies inside the obstacle (sim/obstacle.h).
#ifndef RIPPLE_SIM_OBSTACLE_COVER_H_
#define RIPPLE_SIM_OBSTACLE_COVER_H_

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/grid.h"
#include "sim/obstacle.h"

namespace ripple::sim {

struct ObstacleCover {
  // Bounding region [i0, i1) x [j0, j1) (empty when the obstacle misses the
  // surface) and one byte per cell of it, row-major.
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  std::vector<std::uint8_t> covers;

  bool empty() const { return i0 >= i1 || j0 >= j1; }
  bool Covers(int i, int j) const {
    return covers[static_cast<std::size_t>(j - j0) * (i1 - i0) + (i - i0)] != 0;
  }
};

// Rasterises `obstacle` (at its tank_from_obstacle pose) onto `grid`.
void RasterizeObstacle(const GridSpec& grid, const Obstacle& obstacle,
                       ObstacleCover* cover);

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_OBSTACLE_COVER_H_
