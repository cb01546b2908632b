// Makes the water model the options name (sim/water_surface.h).
#ifndef RIPPLE_SIM_WATER_FACTORY_H_
#define RIPPLE_SIM_WATER_FACTORY_H_

#include <memory>
#include <string>

#include "sim/water_surface.h"

namespace ripple::sim {

// nullptr and one line in `error` on an invalid grid or options.
std::unique_ptr<WaterSurface> CreateWater(const GridSpec& grid,
                                          const WaterModelOptions& options,
                                          std::string* error);

// The default grid of a model for a tank (metres): the capillary-gravity
// model resolves 4 mm ripples (>= 6 cells, ~0.63 mm cells over 170 mm) on
// sizes its cosine transforms are fast for; the paper's scheme uses nx cells.
GridSpec DefaultGrid(WaveModel model, double size_x_m, double size_y_m,
                     double rest_level_m, int nx);

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_WATER_FACTORY_H_
