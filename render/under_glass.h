// What the board under a glass wall sees around it (internal to render/):
// the hemisphere above a point of the board under the middle of each wall's
// slab, traced through the glass, the water and the air of the flat tank
// (tank_paths.h). From inside the slab the point sees the sky through the
// top face and the outer face, the board around the tank, the tank's floor
// through the inner face and the water, and, by the faces' total internal
// reflection, the board under the glass itself. WaterShading::under_glass
// (optics.h) weighs each by its light.
#ifndef RIPPLE_RENDER_UNDER_GLASS_H_
#define RIPPLE_RENDER_UNDER_GLASS_H_

#include "render/optics.h"
#include "render/scene.h"

namespace ripple::render::internal {

// Traces side x side cosine-distributed directions (stratified) from the
// board under the slab's middle of the walls +x and +y, halfway along
// them; the -x and -y walls are their mirror images. The tank's water is
// at rest at tank.water_level.
UnderGlassView TraceUnderGlassView(const TankGeometry& tank,
                                   const WaterOptics& optics, int side = 96);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_UNDER_GLASS_H_
