// The water surface view of the simulation: geometry/height_field.h (grid
// convention there). The pointers of a view from Water::View() stay valid
// until the Water object is destroyed or its grid is replaced; the data
// changes only inside Water::Advance / setters, and `counter` changes
// whenever it does.
#ifndef RIPPLE_SIM_HEIGHT_FIELD_H_
#define RIPPLE_SIM_HEIGHT_FIELD_H_

#include <algorithm>
#include <cstddef>
#include <vector>

#include "geometry/height_field.h"

namespace ripple::sim {

template <typename T>
using BasicHeightFieldView = geometry::BasicHeightFieldView<T>;
using HeightFieldView = geometry::HeightFieldView;

// Surface slopes at the cell centres (dimensionless, dz/dx and dz/dy) by
// central differences, one-sided at the tank walls and next to obstacles.
// The outward surface normal is normalise(-dzdx, -dzdy, 1). Resizes both.
void ComputeGradients(const HeightFieldView& view, std::vector<float>* dzdx,
                      std::vector<float>* dzdy);

// Surface displacement at a tank-frame point (metres), bilinear between cell
// centres and clamped to the grid; the view must hold at least 2 x 2 cells.
template <typename T>
double HeightAt(const BasicHeightFieldView<T>& view, double x_m, double y_m) {
  const int nx = view.nx, ny = view.ny;
  const double fx =
      std::clamp(x_m / view.cell_m + 0.5 * nx - 0.5, 0.0, nx - 1.0);
  const double fy =
      std::clamp(y_m / view.cell_m + 0.5 * ny - 0.5, 0.0, ny - 1.0);
  const int i0 = std::min(static_cast<int>(fx), nx - 2);
  const int j0 = std::min(static_cast<int>(fy), ny - 2);
  const double ax = fx - i0, ay = fy - j0;
  const T* r0 = view.heights + static_cast<std::size_t>(j0) * nx;
  const T* r1 = r0 + nx;
  return (1 - ay) * ((1 - ax) * r0[i0] + ax * r0[i0 + 1]) +
         ay * ((1 - ax) * r1[i0] + ax * r1[i0 + 1]);
}

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_HEIGHT_FIELD_H_
