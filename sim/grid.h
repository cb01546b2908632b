// The simulation grid: nx x ny square cells of edge cell_m, centred on the
// tank centre (cell-centre convention in sim/height_field.h).
#ifndef RIPPLE_SIM_GRID_H_
#define RIPPLE_SIM_GRID_H_

#include <string>

namespace ripple::sim {

struct GridSpec {
  int nx = 128;
  int ny = 83;
  double cell_m = 0.17 / 128;   // metres
  double rest_level_m = 0.025;  // rest surface above the floor, metres

  // nx cells along the tank's long side (tank x); ny = round(size_y/cell),
  // at least 2. Sizes in metres.
  static GridSpec ForTank(double size_x_m, double size_y_m, double rest_level_m,
                          int nx);
  // The smallest grid with at least nx_min cells along x whose sides both
  // factor into 2, 3, 5 and 7 (fast cosine transforms) and whose y extent is
  // within one cell of size_y; falls back to ForTank(nx_min) when no such
  // grid exists below 2*nx_min.
  static GridSpec ForTankFast(double size_x_m, double size_y_m,
                              double rest_level_m, int nx_min);
  // 2 <= nx, ny <= 16384, nx*ny <= 2^26, finite positive cell, finite level.
  bool IsValid(std::string* error) const;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_GRID_H_
