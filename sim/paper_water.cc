#include "sim/paper_water.h"

namespace ripple::sim {

std::unique_ptr<PaperWater> PaperWater::Create(const GridSpec& grid,
                                               const WaterModelOptions& options,
                                               std::string* error) {
  if (!grid.IsValid(error)) return nullptr;
  if (options.waves != WaveModel::kPaper) {
    if (error) *error = "PaperWater runs the paper's scheme only";
    return nullptr;
  }
  if (!options.paper.IsValid(error)) return nullptr;
  return std::unique_ptr<PaperWater>(new PaperWater(grid, options));
}

bool PaperWater::SetOptions(const WaterModelOptions& options,
                            std::string* error) {
  if (options.waves != WaveModel::kPaper) {
    if (error) *error = "the wave model cannot change at run time";
    return false;
  }
  if (!water_.SetOptions(options.paper, error)) return false;
  options_ = options;
  return true;
}

bool PaperWater::RemoveObstacle(int id) {
  if (!water_.RemoveObstacle(id)) return false;
  ++removed_;
  return true;
}

}  // namespace ripple::sim
