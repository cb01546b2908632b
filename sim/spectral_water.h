// Capillary-gravity water on a rectangular tank, solved exactly per mode.
//
// Linear waves on water of depth H obey, for every standing wave
// X_ab(t) * C_a(x) * C_b(y) of the tank (sim/cosine_transform.h; cosine modes
// are exactly the reflecting-wall solutions),
//   X'' + 2*gamma(k)*X' + omega(k)^2 * X = source
// with the dispersion relation and viscous decay of sim/dispersion.h. The
// state is kept as the modal amplitudes and velocities (X, X'); a sub-step of
// dt multiplies each pair by the exact 2x2 propagator of its own
// oscillator, so every wavelength runs at its own phase speed and dies at its
// own rate, for any dt (unconditionally stable, no numerical dispersion).
// Only modes longer than shortest_wavelength_m are simulated; heights are
// synthesised once per changed frame (FFTW cosine transforms over the band's
// rows).
//
// Why modal rather than iWave's convolution kernel (Tessendorf 2004): at a
// 0.63 mm cell the shortest capillary waves have omega ~ 3000 rad/s, so an
// explicit step needs dt < 0.7 ms (~50 sub-steps of a 13x13 kernel per
// frame); the modal propagator has no step limit and costs one transform per
// frame. Its price is that obstacles and absorbing walls are not modes of
// the tank: they are imposed every boundary_step_s. The surface inside an
// obstacle is held at the mean level (iWave's obstruction; waves reflect
// from it), evaluated and corrected on the band's modes over the obstacles'
// bounding box only (sim/band_box.h); a sponge band along the walls relaxes
// waves away (full transforms); the volume they move is restored.
// Obstacles thinner than the depth let some long-wave motion through: the
// model has no flow beneath the surface to block.
//
// The pen (PenModel::kDisplace) acts in two ways:
//  - volume: a vertical shaft of radius r_s whose tip is a depth D below the
//    mean surface displaces V = pi * r_s^2 * D. Each sub-step adds the change
//    of V, spread as K(x - tip) (a unit-volume Gaussian of standard deviation
//    pen_radius/2), so dipping in and lifting out send out ring waves and the
//    level rises by V over the tank's area;
//  - motion: water flows around a shaft moving at speed U, and the surface
//    feels the dynamic pressure p/rho = C * U^2 / 2 over the same footprint.
//    A moving pressure patch is the classical source of capillary-gravity
//    wakes (Raphael & de Gennes, Phys. Rev. E 53, 3448, 1996): no steady wake
//    below the minimum phase speed 0.23 m/s, capillary ripples ahead and
//    gravity waves behind above it. In linear potential flow the pressure
//    drives mode k as X'' = ... - k tanh(kH) p_k / rho.
#ifndef RIPPLE_SIM_SPECTRAL_WATER_H_
#define RIPPLE_SIM_SPECTRAL_WATER_H_

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/band_box.h"
#include "sim/cosine_transform.h"
#include "sim/obstacle_cover.h"
#include "sim/pen_path.h"
#include "sim/substep_clock.h"
#include "sim/water_surface.h"

namespace ripple::sim {

class SpectralWater final : public WaterSurface {
 public:
  // Returns nullptr and `error` on an invalid grid (or a rest level <= 0:
  // the depth) or options.
  static std::unique_ptr<SpectralWater> Create(const GridSpec& grid,
                                               const WaterModelOptions& options,
                                               std::string* error);

  const GridSpec& grid() const override { return grid_; }
  const WaterModelOptions& options() const override { return options_; }
  bool SetOptions(const WaterModelOptions& options,
                  std::string* error) override;
  bool SetPenTip(const std::array<double, 3>& tip_in_tank) override;
  void ClearPen() override { pending_present_ = false; }
  int AddObstacle(const Obstacle& obstacle, std::string* error) override;
  bool SetObstaclePose(int id,
                       const RigidTransform& tank_from_obstacle) override;
  bool RemoveObstacle(int id) override;
  int num_obstacles() const override;
  bool Advance(double dt_frame_s) override;
  const AdvanceStats& stats() const override { return stats_; }
  bool at_rest() const override { return at_rest_; }
  void Reset() override;
  bool SetState(const std::vector<float>& heights_m,
                const std::vector<float>* velocities_m_per_s) override;
  bool AddHeights(const std::vector<float>& dh_m) override;
  HeightFieldView View() const override;
  // Synthesised lazily into buffers the object owns (single owner, like
  // every other call); its cells inside obstacles carry the band's surface
  // rather than the mean level (the obstacles hide them).
  HeightFieldView CoarseView() const override;
  double HeightAtPoint(double x_m, double y_m) const override;
  std::uint64_t counter() const override { return counter_; }

  // Modal amplitude X_ab (metres) and the wave number of mode (a, b), rad/m.
  double ModeAmplitude(int a, int b) const;
  double ModeWaveNumber(int a, int b) const;
  // Modes simulated along x and y (the band of shortest_wavelength_m).
  int band_nx() const { return band_nx_; }
  int band_ny() const { return band_ny_; }
  // Volume the pen displaces now, m^3.
  double pen_volume_m3() const { return pen_volume_m3_; }
  // Water volume: sum over water cells of h*d^2 minus the pen's displaced
  // volume, m^3; constant up to rounding in a closed tank.
  double WaterVolume() const;

 private:
  SpectralWater(const GridSpec& grid, const WaterModelOptions& options);

  struct ObstacleSlot {
    Obstacle obstacle;
    ObstacleCover cover;
    bool active = true;
  };
  // A pen source evaluated at one time: unit-volume kernel coefficients
  // along x and y and the displaced volume (displacement model), or the push
  // kernel and its strength (paper push).
  struct PenState {
    double volume_m3 = 0;
    double x_m = 0, y_m = 0;
    double pressure = 0;  // p/rho on the surface under the shaft, m^2/s^2
    bool push = false;    // paper push acting
  };

  void BuildPropagator();
  bool BoundaryActive() const;
  int BoundaryEverySteps() const;
  // The pen at time t (sub-step end): fills `state`, true when it differs
  // from the current one (a source acts).
  bool PenStateAt(double time_s, double dt_s, PenState* state) const;
  // 1-D cosine coefficients (the band's) of a unit Gaussian kernel of
  // standard deviation sigma_m centred at centre_m along an axis of n
  // cells: its samples sum to 1/cell; only the first `band` coefficients
  // are computed. Returns the factor (sum of the peak-1 samples times the
  // cell) that turns it into the peak-1 Gaussian.
  double KernelCoefficients(double centre_m, int n, int band, double sigma_m,
                            float* out);
  void StepModes(const PenState& next);
  void ImposeBoundaries();
  // After X_/Y_ were replaced: band, heights, volume target, wake.
  void StateReplaced();
  // Zeroes the modes outside the simulated band (after an analysis).
  void ClearOutOfBand();
  void RebuildMask();
  void Synthesize();
  void ComputeStats();
  void SnapToRest();
  double MeanDisplacement() const { return X_[0]; }

  GridSpec grid_;
  WaterModelOptions options_;
  CosineTransform2D transform_;
  // The coarse grid of CoarseView() (nullptr: the grid itself) and its
  // lazily synthesised heights, valid for coarse_counter_.
  std::unique_ptr<CosineTransform2D> coarse_transform_;
  double coarse_cell_m_ = 0;
  mutable AlignedFloats coarse_h_, coarse_x_, coarse_scratch_;
  mutable std::uint64_t coarse_counter_ = ~std::uint64_t{0};
  std::vector<std::uint8_t> coarse_water_;
  void ChooseCoarseGrid();
  std::size_t n_ = 0;
  int band_nx_ = 1,
      band_ny_ = 1;      // modes simulated: a < band_nx_, b < band_ny_
  AlignedFloats X_, Y_;  // modal amplitude, m; velocity, m/s
  AlignedFloats m11_, m12_, m21_, m22_;   // per-mode propagator over substep
  AlignedFloats omega2_;                  // omega^2 per mode, (rad/s)^2
  AlignedFloats h_, v_, scratch_;         // cell domain
  AlignedFloats pressure_weight_;         // k tanh(kH) per mode, rad/m
  std::vector<float> kx_, ky_, px_, py_;  // pen kernel coefficients
  std::vector<float> cell_scratch_;
  std::vector<std::uint8_t> water_;  // 1 water, 0 obstacle
  std::vector<std::uint16_t> cover_count_;
  std::vector<std::int32_t> obstacle_cells_;
  // Cells the obstruction acts on and the share of their motion it keeps.
  std::vector<std::int32_t> soft_cells_;
  std::vector<float> soft_keep_;
  // The soft cells' bounding box, its band-limited transforms and fields.
  BandBoxTransform box_;
  std::vector<float> box_h_, box_v_, box_keep_;
  std::vector<std::uint8_t> box_water_;
  void ImposeObstaclesInBox();
  std::vector<float> sponge_;  // per cell relaxation factor (absorb walls)
  std::vector<ObstacleSlot> obstacles_;
  int num_water_ = 0;

  PenPath path_;
  bool pending_present_ = false;
  std::array<double, 3> pending_tip_ = {0, 0, 0};
  PenState pen_;
  double pen_volume_m3_ = 0;
  double time_s_ = 0;
  SubstepClock clock_;
  int steps_since_boundary_ = 0;
  // Target of WaterVolume() for the boundary step's volume correction.
  double water_volume_m3_ = 0;

  bool at_rest_ = true;
  bool wake_pending_ = false;
  std::uint64_t counter_ = 0;
  AdvanceStats stats_;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_SPECTRAL_WATER_H_
