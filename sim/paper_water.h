// The paper's finite-difference scheme (sim/water.h) behind the WaterSurface
// interface: `--waves paper`.
#ifndef RIPPLE_SIM_PAPER_WATER_H_
#define RIPPLE_SIM_PAPER_WATER_H_

#include <memory>
#include <string>

#include "sim/water.h"
#include "sim/water_surface.h"

namespace ripple::sim {

class PaperWater final : public WaterSurface {
 public:
  // nullptr and `error` on an invalid grid or options (options.paper).
  static std::unique_ptr<PaperWater> Create(const GridSpec& grid,
                                            const WaterModelOptions& options,
                                            std::string* error);

  const GridSpec& grid() const override { return water_.grid(); }
  const WaterModelOptions& options() const override { return options_; }
  bool SetOptions(const WaterModelOptions& options,
                  std::string* error) override;
  bool SetPenTip(const std::array<double, 3>& tip_in_tank) override {
    return water_.SetPenTip(tip_in_tank);
  }
  void ClearPen() override { water_.ClearPen(); }
  int AddObstacle(const Obstacle& obstacle, std::string* error) override {
    return water_.AddObstacle(obstacle, error);
  }
  bool SetObstaclePose(int id,
                       const RigidTransform& tank_from_obstacle) override {
    return water_.SetObstaclePose(id, tank_from_obstacle);
  }
  bool RemoveObstacle(int id) override;
  int num_obstacles() const override {
    return water_.num_obstacles() - removed_;
  }
  bool Advance(double dt_frame_s) override {
    return water_.Advance(dt_frame_s);
  }
  const AdvanceStats& stats() const override { return water_.stats(); }
  bool at_rest() const override { return water_.at_rest(); }
  void Reset() override { water_.Reset(); }
  bool SetState(const std::vector<float>& heights_m,
                const std::vector<float>* velocities_m_per_s) override {
    return water_.SetState(heights_m, velocities_m_per_s);
  }
  bool AddHeights(const std::vector<float>& dh_m) override;
  HeightFieldView View() const override { return water_.View(); }
  double HeightAtPoint(double x_m, double y_m) const override {
    return water_.HeightAtPoint(x_m, y_m);
  }
  std::uint64_t counter() const override { return water_.counter(); }

  // The scheme itself, for its own statistics and tests.
  const Water& scheme() const { return water_; }

 private:
  PaperWater(const GridSpec& grid, const WaterModelOptions& options)
      : options_(options), water_(grid, options.paper) {}

  WaterModelOptions options_;
  Water water_;
  int removed_ = 0;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_PAPER_WATER_H_
