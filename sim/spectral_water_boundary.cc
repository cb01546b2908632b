// SpectralWater's obstacles and walls: the cells they block, the soft
// obstruction weights and the boundary step that imposes them on the modes
// (sim/spectral_water.h).
#include <algorithm>
#include <cmath>

#include "sim/spectral_water.h"

namespace ripple::sim {

int SpectralWater::AddObstacle(const Obstacle& obstacle, std::string* error) {
  if (!obstacle.IsValid(error)) return -1;
  ObstacleSlot slot;
  slot.obstacle = obstacle;
  RasterizeObstacle(grid_, obstacle, &slot.cover);
  obstacles_.push_back(std::move(slot));
  RebuildMask();
  return static_cast<int>(obstacles_.size()) - 1;
}

bool SpectralWater::SetObstaclePose(int id,
                                    const RigidTransform& tank_from_obstacle) {
  if (id < 0 || id >= static_cast<int>(obstacles_.size()) ||
      !obstacles_[id].active || !tank_from_obstacle.IsFinite())
    return false;
  ObstacleSlot& slot = obstacles_[id];
  if (slot.obstacle.tank_from_obstacle == tank_from_obstacle) return true;
  slot.obstacle.tank_from_obstacle = tank_from_obstacle;
  RasterizeObstacle(grid_, slot.obstacle, &slot.cover);
  RebuildMask();
  return true;
}

bool SpectralWater::RemoveObstacle(int id) {
  if (id < 0 || id >= static_cast<int>(obstacles_.size()) ||
      !obstacles_[id].active)
    return false;
  obstacles_[id].active = false;
  obstacles_[id].cover = ObstacleCover();
  RebuildMask();
  return true;
}

int SpectralWater::num_obstacles() const {
  return static_cast<int>(
      std::count_if(obstacles_.begin(), obstacles_.end(),
                    [](const ObstacleSlot& s) { return s.active; }));
}

void SpectralWater::RebuildMask() {
  const int nx = grid_.nx;
  std::fill(cover_count_.begin(), cover_count_.end(), 0);
  for (const ObstacleSlot& s : obstacles_) {
    if (!s.active || s.cover.empty()) continue;
    for (int j = s.cover.j0; j < s.cover.j1; ++j)
      for (int i = s.cover.i0; i < s.cover.i1; ++i)
        if (s.cover.Covers(i, j))
          ++cover_count_[static_cast<std::size_t>(j) * nx + i];
  }
  const std::vector<std::uint8_t> old = water_;
  num_water_ = 0;
  obstacle_cells_.clear();
  for (std::size_t c = 0; c < n_; ++c) {
    water_[c] = cover_count_[c] == 0;
    num_water_ += water_[c];
    if (!water_[c]) obstacle_cells_.push_back(static_cast<std::int32_t>(c));
  }
  // The obstruction's weight: the obstacle indicator averaged over a
  // (2R+1)^2 box, so it rises over ~2R cells instead of in one. A hard edge
  // would put energy into the shortest capillary modes (omega^2 ~ k^3) at
  // every boundary step and can grow without bound next to thin obstacles.
  soft_cells_.clear();
  soft_keep_.clear();
  if (!obstacle_cells_.empty()) {
    constexpr int R = 1;
    const int ny = grid_.ny;
    std::vector<float> blocked(n_, 0.0f);
    for (std::int32_t c : obstacle_cells_) blocked[c] = 1.0f;
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        float sum = 0;
        int count = 0;
        for (int dj = -R; dj <= R; ++dj)
          for (int di = -R; di <= R; ++di) {
            const int ii = std::clamp(i + di, 0, nx - 1);
            const int jj = std::clamp(j + dj, 0, ny - 1);
            sum += blocked[static_cast<std::size_t>(jj) * nx + ii];
            ++count;
          }
        const std::size_t c = static_cast<std::size_t>(j) * nx + i;
        const float m =
            blocked[c] > 0 ? std::max(sum / count, 0.5f) : sum / count;
        if (m <= 0) continue;
        soft_cells_.push_back(static_cast<std::int32_t>(c));
        soft_keep_.push_back(1.0f - m);
      }
    }
  }
  // The box path pays off while the box is small against the grid.
  int bi0 = nx, bi1 = 0, bj0 = grid_.ny, bj1 = 0;
  for (std::int32_t c : soft_cells_) {
    bi0 = std::min(bi0, c % nx);
    bi1 = std::max(bi1, c % nx + 1);
    bj0 = std::min(bj0, c / nx);
    bj1 = std::max(bj1, c / nx + 1);
  }
  box_ = BandBoxTransform();
  if (!soft_cells_.empty() &&
      static_cast<double>(bi1 - bi0) * (bj1 - bj0) < 0.25 * n_) {
    box_.Reset(nx, grid_.ny, band_nx_, band_ny_, bi0, bi1, bj0, bj1);
    const std::size_t w = bi1 - bi0, n = w * (bj1 - bj0);
    box_h_.assign(n, 0.0f);
    box_v_.assign(n, 0.0f);
    box_keep_.assign(n, 1.0f);
    box_water_.assign(n, 1);
    for (std::size_t k = 0; k < soft_cells_.size(); ++k) {
      const int i = soft_cells_[k] % nx, j = soft_cells_[k] / nx;
      box_keep_[(j - bj0) * w + (i - bi0)] = soft_keep_[k];
    }
    for (int j = bj0; j < bj1; ++j)
      for (int i = bi0; i < bi1; ++i)
        box_water_[(j - bj0) * w + (i - bi0)] =
            water_[static_cast<std::size_t>(j) * nx + i];
  }
  if (old != water_) {
    ++counter_;
    wake_pending_ = true;
  }
}

bool SpectralWater::BoundaryActive() const {
  return !obstacle_cells_.empty() ||
         (options_.spectral.walls == WallMode::kAbsorb && !sponge_.empty());
}

int SpectralWater::BoundaryEverySteps() const {
  return std::max(
      1, static_cast<int>(std::lround(options_.spectral.boundary_step_s /
                                      options_.spectral.substep_s)));
}

void SpectralWater::ImposeObstaclesInBox() {
  // The same obstruction as below, on the band's surface at the box's cells
  // only; the change is added back to the band's modes.
  box_.Synthesize(X_.data(), box_h_.data());
  box_.Synthesize(Y_.data(), box_v_.data());
  const float mean = X_[0];
  double obstacle_sum = 0, water_change = 0;
  for (std::size_t k = 0; k < box_h_.size(); ++k) {
    const float h = box_h_[k], drop = 1.0f - box_keep_[k];
    const float dh = (mean - h) * drop;
    box_h_[k] = dh;
    box_v_[k] = -box_v_[k] * drop;
    if (box_water_[k])
      water_change += dh;
    else
      obstacle_sum += h;
  }
  box_.AddAnalysis(box_h_.data(), X_.data());
  box_.AddAnalysis(box_v_.data(), Y_.data());
  // Volume over the water cells: all cells (n * mean) less the obstacle
  // cells, plus what the obstruction moved; the difference to the target is
  // spread evenly (the mean mode).
  if (num_water_ > 0) {
    const double d2 = grid_.cell_m * grid_.cell_m;
    const double sum =
        static_cast<double>(n_) * mean - obstacle_sum + water_change;
    X_[0] += static_cast<float>(
        ((water_volume_m3_ + pen_volume_m3_) / d2 - sum) / num_water_);
  }
}

void SpectralWater::ImposeBoundaries() {
  if (sponge_.empty() && !box_.empty()) {
    ImposeObstaclesInBox();
    return;
  }
  transform_.Synthesize(X_.data(), h_.data(), scratch_.data());
  transform_.Synthesize(Y_.data(), v_.data(), scratch_.data());
  float* h = h_.data();
  float* v = v_.data();
  // Obstructions as in iWave (Tessendorf 2004): the surface inside an
  // obstacle is held at the mean level and still, so waves reflect from its
  // edge (with a change of sign, as from a fixed end). A mirrored fill
  // (Neumann) was tried and grows without bound next to thin obstacles.
  const float mean = X_[0];
  for (std::size_t k = 0; k < soft_cells_.size(); ++k) {
    const std::int32_t c = soft_cells_[k];
    const float keep = soft_keep_[k];
    h[c] = mean + (h[c] - mean) * keep;
    v[c] *= keep;
  }
  if (!sponge_.empty()) {
    for (std::size_t c = 0; c < n_; ++c) {
      const float f = sponge_[c];
      h[c] = mean + (h[c] - mean) * f;
      v[c] *= f;
    }
  }
  // Volume: the water keeps its own volume plus what the pen displaces.
  double sum = 0;
  for (std::size_t c = 0; c < n_; ++c)
    if (water_[c]) sum += h[c];
  const double d2 = grid_.cell_m * grid_.cell_m;
  if (num_water_ > 0) {
    const float shift = static_cast<float>(
        ((water_volume_m3_ + pen_volume_m3_) / d2 - sum) / num_water_);
    for (std::size_t c = 0; c < n_; ++c) h[c] += shift;
  }
  transform_.Analyze(h_.data(), X_.data());
  transform_.Analyze(v_.data(), Y_.data());
  ClearOutOfBand();
}

}  // namespace ripple::sim
