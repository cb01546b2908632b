// The water as the rest of Ripple sees it: a height field that a pen and
// obstacles act on and that advances by frame times. Two models implement it
// (sim/water_factory.h): the capillary-gravity spectral model
// (sim/spectral_water.h, the default) and the paper's finite-difference
// scheme (sim/paper_water.h).
//
// Per frame the app does:
//   water->SetPenTip(tip_in_tank)   // or ClearPen() when the pen is not seen
//   water->SetObstaclePose(id, tank_from_obstacle)   // moving obstacles only
//   water->Advance(dt_frame_s);
//   if (water->View().counter != last) { upload heights; last = counter; }
#ifndef RIPPLE_SIM_WATER_SURFACE_H_
#define RIPPLE_SIM_WATER_SURFACE_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/grid.h"
#include "sim/height_field.h"
#include "sim/obstacle.h"
#include "sim/transform.h"
#include "sim/water.h"
#include "sim/water_options.h"

namespace ripple::sim {

class WaterSurface {
 public:
  virtual ~WaterSurface() = default;

  virtual const GridSpec& grid() const = 0;
  virtual const WaterModelOptions& options() const = 0;
  // Runtime changes of the model's options (not of `waves`). On an invalid
  // value returns false, fills `error` and changes nothing.
  virtual bool SetOptions(const WaterModelOptions& options,
                          std::string* error) = 0;

  // Pen tip in the tank frame (metres) at the END of the next Advance()
  // interval; false (changing nothing) for a non-finite coordinate.
  virtual bool SetPenTip(const std::array<double, 3>& tip_in_tank) = 0;
  // The pen is not seen from the next interval on.
  virtual void ClearPen() = 0;

  // Adds an obstacle (validated); its id (>= 0), or -1 and `error`.
  virtual int AddObstacle(const Obstacle& obstacle, std::string* error) = 0;
  // Moves obstacle `id`; false for an unknown or removed id or a non-finite
  // pose.
  virtual bool SetObstaclePose(int id,
                               const RigidTransform& tank_from_obstacle) = 0;
  // Takes obstacle `id` out of the water (its cells become water at the
  // current mean level); ids of the others are kept. False if unknown.
  virtual bool RemoveObstacle(int id) = 0;
  // Obstacles added and not removed.
  virtual int num_obstacles() const = 0;

  // Advances by dt_frame_s seconds (>= 0, finite; otherwise false). At rest
  // with nothing touching it returns at once with stats().changed == false.
  virtual bool Advance(double dt_frame_s) = 0;
  virtual const AdvanceStats& stats() const = 0;
  virtual bool at_rest() const = 0;
  // Flat water at rest (obstacles kept).
  virtual void Reset() = 0;
  // Replaces the state: heights in metres above rest and optional
  // velocities dh/dt in m/s, nx*ny each; false on a size mismatch or a
  // non-finite value. Wakes the water.
  virtual bool SetState(const std::vector<float>& heights_m,
                        const std::vector<float>* velocities_m_per_s) = 0;

  // Adds a displacement (metres, nx*ny) to the surface, keeping its
  // velocities: a drop released from rest. False on a size mismatch or a
  // non-finite value. Wakes the water.
  virtual bool AddHeights(const std::vector<float>& dh_m) = 0;

  virtual HeightFieldView View() const = 0;
  // The same surface on the coarsest square grid over the tank that still
  // holds every simulated wavelength (exact samples of the band-limited
  // surface), for consumers whose cost grows with the cell count (the
  // caustics). Models without a band limit return View().
  virtual HeightFieldView CoarseView() const { return View(); }
  // Bilinear surface displacement at a tank-frame point (clamped), metres.
  virtual double HeightAtPoint(double x_m, double y_m) const = 0;
  virtual std::uint64_t counter() const = 0;
};

}  // namespace ripple::sim

#endif  // RIPPLE_SIM_WATER_SURFACE_H_
