// The water surface of the reference renderer (internal): z = level +
// h(x, y), h the bicubic Catmull-Rom interpolant of the height field's cell
// centres (render/scene.h), continued beyond the outermost centres by
// mirroring the cells about the grid's edge (the surface meets a grid edge
// level, as at a reflecting wall). The interpolant is C1, so normals are
// continuous and caustics show no seams along cell edges (bilinear patches
// would give piecewise-constant slopes and streaks on the floor).
#ifndef RIPPLE_RENDER_REFERENCE_SURFACE_H_
#define RIPPLE_RENDER_REFERENCE_SURFACE_H_

#include <array>
#include <glm/glm.hpp>
#include <vector>

#include "render/scene.h"

namespace ripple::reference::internal {

class WaterSurface {
 public:
  // `view` may have null heights (flat water at `level`). The patches cover
  // |x| <= half_x, |y| <= half_y (metres, the inner tank); outside them the
  // edge patch is held constant.
  void Init(const render::HeightFieldView& view, double level, double half_x,
            double half_y);

  bool flat() const { return flat_; }
  double level() const { return level_; }
  // Bounds of z over the surface (conservative for the interpolant).
  double z_min() const { return z_min_; }
  double z_max() const { return z_max_; }
  // Surface z and its gradient (dz/dx, dz/dy) at (x, y).
  double Z(double x, double y, double* gx = nullptr,
           double* gy = nullptr) const;
  // Upward unit normal (-dz/dx, -dz/dy, 1) / norm.
  glm::dvec3 Normal(double x, double y) const;

  // The first t in [t0, t1] where o + t d crosses the surface: from above
  // (z > surface at t0) when `from_above`, else from below. Walks tiles of
  // 2 x 2 patches with rigorous z bounds (skipping where the ray passes
  // above or below them), samples every quarter cell inside the bounds and
  // refines a sign change by Illinois false position to |z - surface| <
  // 1e-13 m (or a bracket under 1e-12 m). A crest or trough that the ray
  // enters and leaves between two samples a quarter cell apart is missed
  // (grazing rays only).
  bool Intersect(const glm::dvec3& o, const glm::dvec3& d, double t0, double t1,
                 bool from_above, double* t) const;

 private:
  // f(t) = z(t) - surface(x(t), y(t)).
  double F(const glm::dvec3& o, const glm::dvec3& d, double t) const;
  double Refine(const glm::dvec3& o, const glm::dvec3& d, double a, double fa,
                double b, double fb) const;

  bool flat_ = true;
  double level_ = 0;
  double cell_ = 1;
  double u_offset_ = 0, v_offset_ = 0;  // patch index = x / cell + offset
  int pi0_ = 0, pj0_ = 0, npx_ = 0, npy_ = 0;
  std::vector<std::array<double, 16>> patches_;  // c[m * 4 + n] s^m t^n
  // Tiles of kTile x kTile patches with z bounds (absolute).
  static constexpr int kTile = 2;
  int ntx_ = 0, nty_ = 0;
  std::vector<double> tile_lo_, tile_hi_;
  double z_min_ = 0, z_max_ = 0;
};

}  // namespace ripple::reference::internal

#endif  // RIPPLE_RENDER_REFERENCE_SURFACE_H_
