#include "sim/water_factory.h"

#include "sim/paper_water.h"
#include "sim/spectral_water.h"

namespace ripple::sim {

std::unique_ptr<WaterSurface> CreateWater(const GridSpec& grid,
                                          const WaterModelOptions& options,
                                          std::string* error) {
  if (options.waves == WaveModel::kPaper)
    return PaperWater::Create(grid, options, error);
  return SpectralWater::Create(grid, options, error);
}

GridSpec DefaultGrid(WaveModel model, double size_x_m, double size_y_m,
                     double rest_level_m, int nx) {
  if (model == WaveModel::kCapillaryGravity)
    return GridSpec::ForTankFast(size_x_m, size_y_m, rest_level_m, nx);
  return GridSpec::ForTank(size_x_m, size_y_m, rest_level_m, nx);
}

}  // namespace ripple::sim
