// Height-field water after Tawara & Ono (2009): a damped wave equation on a
// grid of square cells, driven by a pen, bounded by the tank walls and
// obstacles, and idle when the surface is at rest.
//
// Scheme (the paper's update, in this order, per sub-step of dt seconds):
//   v += dt * (c^2 * lap(h) / d^2 + a_pen)      (v in m/s, d = cell edge)
//   v *= exp(-viscosity * dt)
//   h += dt * v                                 (with the NEW v)
// The state is kept in per-step units u = dt*v, so the kernel is
//   u = D * (u + k*lap(h) + dt^2*a),  h += u,  k = (c*dt/d)^2 = courant^2.
// It is stable for c*dt/d <= 1/sqrt(2); sub-steps use c*dt/d = courant <= 0.5.
//
// Viscosity: an oscillating mode's amplitude decays exactly as
// exp(-viscosity * t / 2) for any dt and wavelength (the step matrix has
// determinant D = exp(-viscosity*dt), so each complex eigenvalue has modulus
// sqrt(D)). 0 means waves forever; modes with k*|lap| small against the
// damping become overdamped ("honey") for large values.
//
// Per frame the app does:
//   water.SetPenTip(tip_in_tank)   // or ClearPen() when the pen is not seen
//   water.SetObstaclePose(id, tank_from_obstacle)   // moving obstacles only
//   water.Advance(dt_frame_s);
//   if (water.View().counter != last) { upload heights; last = counter; }
#ifndef RIPPLE_SIM_WATER_H_
#define RIPPLE_SIM_WATER_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/grid.h"
#include "sim/height_field.h"
#include "sim/obstacle.h"
#include "sim/obstacle_cover.h"
#include "sim/pen_path.h"
#include "sim/substep_clock.h"
#include "sim/transform.h"

namespace ripple::sim {

enum class WallMode {
  kReflect,  // mirrored (Neumann) walls: waves bounce, volume is conserved
  kAbsorb,   // first-order Mur absorbing walls: waves leave the tank
};

enum class ObstacleMode {
  kReflect,  // mirrored boundaries at obstacle cells; conserves volume
  kZero,     // the paper's h = v = 0 inside: leaks volume, inverts reflections
};

struct WaterOptions {
  // Wave speed c, m/s. Shallow water would give sqrt(g*level) (0.5 m/s at
  // 25 mm); slower reads better on a small tank.
  double wave_speed_m_per_s = 0.3;
  // Velocity damping rate, 1/s: v *= exp(-viscosity*dt). Wave amplitude
  // decays as exp(-viscosity*t/2). 0 = waves forever; ~50 = honey.
  double viscosity_per_s = 0.6;
  // Sub-step Courant number c*dt/d, in (0, 0.5]; dt = courant*d/c seconds.
  double courant = 0.5;
  WallMode walls = WallMode::kReflect;
  ObstacleMode obstacles = ObstacleMode::kReflect;
  // Sub-steps one Advance() may run; the surplus time is dropped.
  int max_substeps = 100;
  // Pen force (the paper): a(rho) = s * exp(-rho^2 / (2*(0.2*r)^2)) pushing
  // the surface down around the tip while the tip is below the surface, with
  // a uniform upward compensation over the water so volume is conserved.
  // s, m/s^2, in [0, 1e12]. (A negative s would pull the surface up onto
  // a submerged tip and keep it there: a runaway, so it is refused.)
  double pen_strength_m_per_s2 = 5.0;
  // r, metres; small r gives high frequencies. The Gaussian's sigma is
  // max(0.2*r, cell/2) so that a tip between cell centres is never lost.
  double pen_radius_m = 0.01;
  // Rest: when max|v| <= rest_speed and max|h - mean| <= rest_height and
  // nothing touches the water, the surface is snapped flat and Advance()
  // does nothing until it is woken.
  double rest_speed_m_per_s = 1e-3;
  double rest_height_m = 1e-5;

  // Every value finite and in range; the first problem goes to `error`.
  bool IsValid(std::string* error) const;
};

// Per-Advance() statistics (computed once per call, not per sub-step).
struct AdvanceStats {
  int substeps = 0;          // sub-steps taken by this call
  double substep_s = 0;      // sub-step length dt, seconds
  double dropped_s = 0;      // frame time dropped (over max_substeps)
  double volume_m3 = 0;      // sum over water cells of h*d^2 (displacement)
  double abs_volume_m3 = 0;  // sum over water cells of |h|*d^2
  // The scheme's exact discrete invariant (DESIGN.md), in physical units:
  // (d^2/dt^2) * 1/2 (|u|^2 + h'Ah - u'Ah), A = -k*lap, m^4/s^2 (energy per
  // unit density and gravity-free, up to a constant). Conserved exactly
  // without viscosity, pen, absorbing walls or moving obstacles.
  double energy = 0;
  double max_abs_height_m = 0;   // max |h| over water cells
  double max_deviation_m = 0;    // max |h - mean h| over water cells
  double max_speed_m_per_s = 0;  // max |v|
  bool pen_touched = false;      // the force acted in some sub-step
  bool changed = false;          // the surface changed (counter moved)
  bool at_rest = false;          // the water is (now) at rest
  std::uint64_t counter = 0;     // change counter after this call

  std::string BriefReport() const;
};

// The simulation. T is float for the app; double is instantiated for the
// exact-invariant tests. Not thread-safe; one owner.
template <typename T>
class BasicWater {
 public:
  // RIPPLE_CHECKs that grid and options are valid: validate user input
  // with IsValid first.
  BasicWater(const GridSpec& grid, const WaterOptions& options);

  const GridSpec& grid() const { return grid_; }
  const WaterOptions& options() const { return options_; }
  // Sub-step length, seconds: courant * cell / wave_speed.
  double substep_s() const { return dt_; }

  // Runtime changes (wave speed, viscosity, pen s and r, thresholds, modes).
  // On an invalid value returns false, fills `error` and changes nothing.
  // A new wave speed rescales the stored velocities so v is continuous.
  bool SetOptions(const WaterOptions& options, std::string* error);

  // Pen tip in the tank frame (metres) at the END of the next Advance()
  // interval; the tip moves linearly from the previous sample across it (and
  // across sub-steps), so a fast stroke leaves a continuous wake. Returns
  // false (and changes nothing) for a NaN or infinite coordinate.
  bool SetPenTip(const std::array<double, 3>& tip_in_tank);
  // The pen is not seen (or out of the water) from the next interval on.
  void ClearPen();

  // Adds an obstacle (validated) and returns its id (>= 0), or -1 and
  // `error`. Its mask is computed now.
  int AddObstacle(const Obstacle& obstacle, std::string* error);
  // Moves obstacle `id`; the mask is recomputed only when the pose differs
  // from the last one. Returns false for an unknown id or non-finite pose.
  bool SetObstaclePose(int id, const RigidTransform& tank_from_obstacle);
  // Takes obstacle `id` out of the water (its cells become water, as the
  // treatment gives them); false for an unknown or already removed id. Ids
  // of the others are kept.
  bool RemoveObstacle(int id);
  // Obstacle slots added so far, removed ones included.
  int num_obstacles() const { return static_cast<int>(obstacles_.size()); }
  // Number of grid cells that are water (not blocked by any obstacle).
  int num_water_cells() const { return num_water_; }

  // Runs the sub-steps due for a frame of dt_frame_s seconds (>= 0, finite;
  // otherwise returns false and does nothing). At rest with nothing touching
  // it returns at once with stats().changed == false.
  bool Advance(double dt_frame_s);
  const AdvanceStats& stats() const { return stats_; }
  bool at_rest() const { return at_rest_; }

  // Runs n bare sub-steps now: no pen, no accumulator, no statistics (for
  // benchmarks and tests). Wakes the water.
  void Step(int n = 1);

  // Replaces the state: heights in metres above rest (nx*ny), velocities in
  // m/s (nx*ny or null for zero). Obstacle cells are forced to the treatment's
  // values. Returns false (changing nothing) on a size mismatch or a
  // non-finite value. Wakes the water.
  bool SetState(const std::vector<T>& heights_m,
                const std::vector<T>* velocities_m_per_s = nullptr);
  // Flat water at rest (obstacles kept).
  void Reset();

  // Heights row-major, heights()[j*nx + i], metres above rest (see
  // height_field.h).
  const T* heights() const { return h_.data(); }
  // Velocity of cell (i, j), m/s.
  double VelocityAt(int i, int j) const;
  const std::uint8_t* water_mask() const { return water_.data(); }
  std::uint64_t counter() const { return counter_; }
  BasicHeightFieldView<T> View() const;

  // Surface displacement at a tank-frame point (bilinear between cell
  // centres, clamped to the grid), metres above rest.
  double HeightAtPoint(double x_m, double y_m) const;

 private:
  // An obstacle and the cells it covers now.
  struct ObstacleState : ObstacleCover {
    Obstacle obstacle;
    bool removed = false;
  };

  void Rasterize(ObstacleState* state) const;
  // Adds (+1) or removes (-1) an obstacle's cover from the count grid.
  void ApplyCover(const ObstacleState& state, int sign);
  // Applies the treatment to cells in the region whose water state flipped;
  // true if any did.
  bool UpdateMaskRegion(int i0, int i1, int j0, int j1);
  // The pen at time_s is inside the grid and below the local surface.
  bool PenTouches(double time_s, std::array<double, 3>* tip) const;
  // Applies the pen's Gaussian for the sub-step at time_s (if it touches)
  // and returns the uniform per-step velocity compensation for water cells.
  bool ApplyPen(double time_s, T* compensation);
  void SubStep(T compensation);
  void SeedGhosts();
  void UpdateGhosts(bool before_step);
  // Statistics pass; also removes the rounding drift of sum(h) and sum(u)
  // when the set-up conserves volume.
  void ComputeStats();
  bool Conserving() const;
  void ResetVolumeTarget();
  void SnapToRest();

  GridSpec grid_;
  WaterOptions options_;
  double dt_ = 0;  // sub-step, seconds
  T k_ = 0;        // courant^2
  T damp_ = 1;     // exp(-viscosity*dt)
  double sigma_m_ = 0;

  std::vector<T> h_, u_;             // nx*ny
  std::vector<T> mask_;              // nx*ny, 1 water / 0 blocked (kernel)
  std::vector<std::uint8_t> water_;  // nx*ny, same as mask_ (for the view)
  std::vector<std::uint16_t> cover_count_;  // obstacles covering each cell
  int num_water_ = 0;
  // Absorbing-wall ghost values (and the edges before the step).
  std::vector<T> ghost_top_, ghost_bottom_, ghost_left_, ghost_right_;
  std::vector<T> edge_top_, edge_bottom_, edge_left_, edge_right_;
  std::vector<T> ones_;
  std::vector<T> pen_gx_, pen_gy_;  // separable Gaussian scratch
  std::vector<ObstacleState> obstacles_;

  PenPath pen_path_;
  bool pending_present_ = false;
  std::array<double, 3> pending_tip_ = {0, 0, 0};
  double time_s_ = 0;  // frame clock (sum of dt_frame minus dropped time)
  SubstepClock clock_;
  double volume_debt_ = 0;  // rounding left over from the pen compensation
  // What sum(h) and sum(u) over the water should be in a conserving set-up.
  double target_volume_ = 0;
  double target_usum_ = 0;

  bool at_rest_ = true;
  bool wake_pending_ = false;
  std::uint64_t counter_ = 0;
  AdvanceStats stats_;
};

using Water = BasicWater<float>;
using WaterD = BasicWater<double>;

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_WATER_H_
