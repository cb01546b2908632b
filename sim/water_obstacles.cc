// BasicWater's obstacles: the cells each one covers, the mask they make and
// the treatment of cells that change between water and obstacle
// (sim/water.h).
#include <algorithm>
#include <cmath>

#include "sim/water.h"

namespace ripple::sim {

template <typename T>
void BasicWater<T>::Rasterize(ObstacleState* state) const {
  RasterizeObstacle(grid_, state->obstacle, state);
}

template <typename T>
void BasicWater<T>::ApplyCover(const ObstacleState& state, int sign) {
  const int w = state.i1 - state.i0;
  for (int j = state.j0; j < state.j1; ++j) {
    for (int i = state.i0; i < state.i1; ++i) {
      if (!state.covers[static_cast<size_t>(j - state.j0) * w + (i - state.i0)])
        continue;
      cover_count_[static_cast<size_t>(j) * grid_.nx + i] += sign;
    }
  }
}

template <typename T>
bool BasicWater<T>::UpdateMaskRegion(int i0, int i1, int j0, int j1) {
  bool changed = false;
  double removed = 0, removed_u = 0;
  for (int j = j0; j < j1; ++j) {
    for (int i = i0; i < i1; ++i) {
      const size_t c = static_cast<size_t>(j) * grid_.nx + i;
      const bool wet = cover_count_[c] == 0;
      if (wet == (water_[c] != 0)) continue;
      changed = true;
      if (!wet) {
        removed += h_[c];
        removed_u += u_[c];
      }
      h_[c] = 0;
      u_[c] = 0;
      water_[c] = wet;
      mask_[c] = wet ? T(1) : T(0);
      num_water_ += wet ? 1 : -1;
    }
  }
  if (changed && options_.obstacles == ObstacleMode::kReflect &&
      num_water_ > 0 && (removed != 0 || removed_u != 0)) {
    // Give the displaced volume (and its velocity, whose sum Σh integrates)
    // back to the water, evenly.
    const T dh = static_cast<T>(removed / num_water_);
    const T du = static_cast<T>(removed_u / num_water_);
    for (size_t c = 0; c < h_.size(); ++c) {
      h_[c] += dh * mask_[c];
      u_[c] += du * mask_[c];
    }
  }
  if (changed && !Conserving()) ResetVolumeTarget();
  return changed;
}

template <typename T>
int BasicWater<T>::AddObstacle(const Obstacle& obstacle, std::string* error) {
  if (!obstacle.IsValid(error)) return -1;
  ObstacleState state;
  state.obstacle = obstacle;
  Rasterize(&state);
  ApplyCover(state, +1);
  if (UpdateMaskRegion(state.i0, state.i1, state.j0, state.j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  obstacles_.push_back(std::move(state));
  return static_cast<int>(obstacles_.size()) - 1;
}

template <typename T>
bool BasicWater<T>::SetObstaclePose(int id,
                                    const RigidTransform& tank_from_obstacle) {
  if (id < 0 || id >= num_obstacles() || !tank_from_obstacle.IsFinite() ||
      obstacles_[id].removed)
    return false;
  ObstacleState& state = obstacles_[id];
  if (state.obstacle.tank_from_obstacle == tank_from_obstacle) return true;
  const int oi0 = state.i0, oi1 = state.i1, oj0 = state.j0, oj1 = state.j1;
  ApplyCover(state, -1);
  state.obstacle.tank_from_obstacle = tank_from_obstacle;
  Rasterize(&state);
  ApplyCover(state, +1);
  // The union of the old and new regions holds every cell that may flip.
  int i0 = state.i0, i1 = state.i1, j0 = state.j0, j1 = state.j1;
  if (oi0 < oi1 && oj0 < oj1) {
    if (i0 < i1 && j0 < j1) {
      i0 = std::min(i0, oi0);
      i1 = std::max(i1, oi1);
      j0 = std::min(j0, oj0);
      j1 = std::max(j1, oj1);
    } else {
      i0 = oi0, i1 = oi1, j0 = oj0, j1 = oj1;
    }
  }
  if (UpdateMaskRegion(i0, i1, j0, j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  return true;
}

template <typename T>
bool BasicWater<T>::RemoveObstacle(int id) {
  if (id < 0 || id >= num_obstacles() || obstacles_[id].removed) return false;
  ObstacleState& state = obstacles_[id];
  ApplyCover(state, -1);
  state.removed = true;
  if (UpdateMaskRegion(state.i0, state.i1, state.j0, state.j1)) {
    ++counter_;
    wake_pending_ = true;
  }
  static_cast<ObstacleCover&>(state) = ObstacleCover();
  return true;
}

template void BasicWater<float>::Rasterize(ObstacleState* state) const;
template void BasicWater<double>::Rasterize(ObstacleState* state) const;
template void BasicWater<float>::ApplyCover(const ObstacleState& state,
                                            int sign);
template void BasicWater<double>::ApplyCover(const ObstacleState& state,
                                             int sign);
template bool BasicWater<float>::UpdateMaskRegion(int i0, int i1, int j0,
                                                  int j1);
template bool BasicWater<double>::UpdateMaskRegion(int i0, int i1, int j0,
                                                   int j1);
template int BasicWater<float>::AddObstacle(const Obstacle& obstacle,
                                            std::string* error);
template int BasicWater<double>::AddObstacle(const Obstacle& obstacle,
                                             std::string* error);
template bool BasicWater<float>::SetObstaclePose(
    int id, const RigidTransform& tank_from_obstacle);
template bool BasicWater<double>::SetObstaclePose(
    int id, const RigidTransform& tank_from_obstacle);
template bool BasicWater<float>::RemoveObstacle(int id);
template bool BasicWater<double>::RemoveObstacle(int id);

}  // namespace ripple::sim
