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

bool PaperWater::AddHeights(const std::vector<float>& dh_m) {
  const int nx = water_.grid().nx, ny = water_.grid().ny;
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  if (dh_m.size() != n) return false;
  std::vector<float> h(water_.heights(), water_.heights() + n), v(n);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * nx + i;
      h[c] += dh_m[c];
      v[c] = static_cast<float>(water_.VelocityAt(i, j));
    }
  return water_.SetState(h, &v);
}

bool PaperWater::RemoveObstacle(int id) {
  if (!water_.RemoveObstacle(id)) return false;
  ++removed_;
  return true;
}

}  // namespace ripple::sim
