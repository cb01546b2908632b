#include "sim/grid.h"

#include <algorithm>
#include <cmath>

namespace ripple::sim {
namespace {

constexpr int kMaxGridSide = 16384;
constexpr double kMaxGridCells = 1 << 26;

bool Finite(double v) { return std::isfinite(v); }

bool FactorsInto2357(int n) {
  if (n < 1) return false;
  for (int p : {2, 3, 5, 7})
    while (n % p == 0) n /= p;
  return n == 1;
}

}  // namespace

GridSpec GridSpec::ForTank(double size_x_m, double size_y_m,
                           double rest_level_m, int nx) {
  GridSpec g;
  g.nx = nx;
  g.cell_m = nx > 0 ? size_x_m / nx : 0;
  const double ny = g.cell_m > 0 ? std::round(size_y_m / g.cell_m) : 0;
  g.ny = Finite(ny) ? static_cast<int>(std::clamp(ny, 2.0, 1e9)) : 0;
  g.rest_level_m = rest_level_m;
  return g;
}

bool GridSpec::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (nx < 2 || ny < 2 || nx > kMaxGridSide || ny > kMaxGridSide)
    return fail("grid must be between 2x2 and " + std::to_string(kMaxGridSide) +
                " cells per side (got " + std::to_string(nx) + "x" +
                std::to_string(ny) + ")");
  if (static_cast<double>(nx) * ny > kMaxGridCells)
    return fail("grid has more than 2^26 cells");
  if (!Finite(cell_m) || !(cell_m > 0))
    return fail("cell size must be a positive number of metres");
  if (!Finite(rest_level_m)) return fail("rest level must be finite");
  return true;
}

GridSpec GridSpec::ForTankFast(double size_x_m, double size_y_m,
                               double rest_level_m, int nx_min) {
  if (nx_min >= 2 && nx_min <= kMaxGridSide / 2 && size_x_m > 0 &&
      size_y_m > 0) {
    for (int nx = nx_min; nx < 2 * nx_min; ++nx) {
      if (!FactorsInto2357(nx)) continue;
      const double cell = size_x_m / nx;
      const int ny0 = static_cast<int>(std::round(size_y_m / cell));
      for (int ny : {ny0, ny0 - 1, ny0 + 1}) {
        if (ny < 2 || !FactorsInto2357(ny)) continue;
        if (std::abs(ny * cell - size_y_m) > cell) continue;
        GridSpec g;
        g.nx = nx;
        g.ny = ny;
        g.cell_m = cell;
        g.rest_level_m = rest_level_m;
        return g;
      }
    }
  }
  return ForTank(size_x_m, size_y_m, rest_level_m, nx_min);
}

}  // namespace ripple::sim
