// The simulation's rigid transform: geometry::Rigid3Matrix, plain numbers so
// that sim/ needs no maths library. `tank_from_obstacle` maps a point
// expressed in the obstacle frame into the tank frame:
// p_in_tank = R * p_in_obstacle + t.
#ifndef RIPPLE_SIM_TRANSFORM_H_
#define RIPPLE_SIM_TRANSFORM_H_

#include "geometry/rigid3_matrix.h"

namespace ripple::sim {

using RigidTransform = geometry::Rigid3dMatrix;

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_TRANSFORM_H_
