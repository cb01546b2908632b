// The read-only view of the water surface that the renderer consumes. It is
// plain data: no sim type needs to be known to use it.
//
// Grid convention (tank frame: origin at the tank centre, x along the long
// side, z up, floor z = 0):
//   - nx x ny square cells of edge cell_m. Cell (i, j) covers
//       x in [x0 + i*cell_m, x0 + (i+1)*cell_m), y likewise with y0, where
//       x0 = -nx*cell_m/2, y0 = -ny*cell_m/2 (the grid is centred on the tank
//       centre; ny*cell_m can differ from the tank's inner size_y by up to
//       one cell because cells are square and sizes are chosen for fast
//       transforms).
//   - heights[j*nx + i] is the surface displacement in metres above the rest
//     level at the cell CENTRE (x0 + (i+0.5)*cell_m, y0 + (j+0.5)*cell_m):
//     the surface point is z = rest_level_m + heights[j*nx + i]. i runs along
//     tank x (contiguous in memory), j along tank y.
//   - water[j*nx + i] is 1 for water and 0 for a cell blocked by an obstacle
//     (its height is meaningless for drawing: 0 or a frozen value).
// The producer (sim::Water) states how long the pointers stay valid; `counter`
// changes whenever the data does.
#ifndef RIPPLE_GEOMETRY_HEIGHT_FIELD_H_
#define RIPPLE_GEOMETRY_HEIGHT_FIELD_H_

#include <cstddef>
#include <cstdint>

namespace ripple::geometry {

template <typename T>
struct BasicHeightFieldView {
  const T* heights = nullptr;           // nx*ny, metres above rest level
  const std::uint8_t* water = nullptr;  // nx*ny, 1 = water, 0 = obstacle
  int nx = 0;
  int ny = 0;
  double cell_m = 0;          // square cell edge, metres
  double rest_level_m = 0;    // rest surface height above the floor, metres
  std::uint64_t counter = 0;  // changes whenever heights or water change

  // Tank-frame x, y of the centre of cell (i, j), metres.
  double CellCentreX(int i) const { return (i + 0.5 - 0.5 * nx) * cell_m; }
  double CellCentreY(int j) const { return (j + 0.5 - 0.5 * ny) * cell_m; }
  T Height(int i, int j) const {
    return heights[static_cast<std::size_t>(j) * nx + i];
  }
  // Absolute surface height above the floor at the centre of cell (i, j).
  double SurfaceZ(int i, int j) const { return rest_level_m + Height(i, j); }
  bool empty() const { return heights == nullptr; }
};

using HeightFieldView = BasicHeightFieldView<float>;

}  // namespace ripple::geometry

#endif  // RIPPLE_GEOMETRY_HEIGHT_FIELD_H_
