// The water surface view of the simulation: geometry/height_field.h (grid
// convention there). The pointers of a view from Water::View() stay valid
// until the Water object is destroyed or its grid is replaced; the data
// changes only inside Water::Advance / setters, and `counter` changes
// whenever it does.
#ifndef RIPPLE_SIM_HEIGHT_FIELD_H_
#define RIPPLE_SIM_HEIGHT_FIELD_H_

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

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_HEIGHT_FIELD_H_
