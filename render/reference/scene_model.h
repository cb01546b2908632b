// The reference renderer's scene as ray-traceable geometry (internal): media,
// the board, the glass walls, the water surface and the opaque solids, with
// the next event along a ray, and the irradiance charts that light tracing
// fills and shading reads.
#ifndef RIPPLE_RENDER_REFERENCE_SCENE_MODEL_H_
#define RIPPLE_RENDER_REFERENCE_SCENE_MODEL_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "render/reference/reference.h"
#include "render/reference/surface.h"

namespace ripple::reference::internal {

using Spectrum = glm::dvec3;  // one value per band, (B, G, R)

// Rays start this far past the point they leave (metres).
constexpr double kRayEpsilon = 1e-9;

enum class Medium { kAir = 0, kWater = 1, kGlass = 2 };

// A texel grid over one diffuse surface, in that surface's (u, v) metres.
struct Chart {
  int nu = 0, nv = 0;
  double du = 0, dv = 0;  // texel size, metres
  bool wrap_u = false;    // cylinder sides
};

// Chart indices: the tank floor, then the board around it, then the solids'.
constexpr int kFloorChart = 0;
constexpr int kBoardChart = 1;

// An opaque Lambertian solid in its own frame: a box centred on its origin,
// or a capped cylinder around its z axis from z0 to z1.
struct Solid {
  enum class Shape { kBox, kCylinder };
  Shape shape = Shape::kBox;
  glm::dmat3 rot{1.0};     // tank_from_local rotation
  glm::dvec3 origin{0.0};  // local origin in the tank frame
  glm::dvec3 half{0.0};    // box half extents
  double radius = 0, z0 = 0, z1 = 0;
  Spectrum albedo{0.5};
  glm::dvec3 bound_centre{0.0};  // bounding sphere, tank frame
  double bound_radius = 0;
  int first_chart = 0;  // box: 6 faces (axis * 2 + positive); cylinder:
                        // side, z0 cap, z1 cap
};

struct Event {
  enum class Kind { kEscape, kInterface, kDiffuse };
  Kind kind = Kind::kEscape;
  double t = 0;
  glm::dvec3 p{0.0};
  glm::dvec3 n{0.0};           // unit normal on the side the ray arrives from
  Medium next = Medium::kAir;  // interfaces: the medium beyond
  int solid = -1;              // diffuse: -1 the board, else a solid
  int chart = -1;              // diffuse: irradiance chart (wet only)
  double u = 0, v = 0;         // chart coordinates, metres
};

class SceneModel {
 public:
  // `texel` is the caustic-map texel (metres). Expects a valid scene.
  void Init(const ReferenceScene& scene, bool dry, double texel);

  // The first event along o + t d (t > kRayEpsilon) for a ray in medium m.
  Event Next(const glm::dvec3& o, const glm::dvec3& d, Medium m) const;
  Spectrum Albedo(const Event& e) const;
  // Whether p lies inside (or on) one of the opaque solids. Next() finds a
  // solid's faces only from outside, so a ray starting inside passes
  // through it: a light path launched inside one is blocked by it instead.
  bool InsideSolid(const glm::dvec3& p) const;
  // The room's wall (ReferenceScene::Room) that the ray o + t d (in the air,
  // o inside the room) meets, at *t, and its radiance; false without a room
  // or when the ray leaves over the walls' top.
  bool RoomWall(const glm::dvec3& o, const glm::dvec3& d, double* t,
                Spectrum* radiance) const;
  double Ior(Medium m) const { return ior_[static_cast<int>(m)]; }

  bool wet() const { return wet_; }
  const std::vector<Chart>& charts() const { return charts_; }
  const std::vector<Solid>& solids() const { return solids_; }
  const WaterSurface& surface() const { return surface_; }
  // Board map rectangle (tank x, y) of kBoardChart.
  cv::Rect2d board_rect() const { return board_rect_; }
  double half_x() const { return a_; }
  double half_y() const { return b_; }
  double outer_half_x() const { return A_; }
  double outer_half_y() const { return B_; }
  double wall_height() const { return H_; }
  // Unit direction towards the light, its angular radius, absorption.
  glm::dvec3 light() const { return light_; }
  double alpha() const { return alpha_; }
  Spectrum sigma() const { return sigma_; }

 private:
  void SolidHits(const glm::dvec3& o, const glm::dvec3& d, Event* best) const;
  void AirEvents(const glm::dvec3& o, const glm::dvec3& d, Event* best) const;
  void TankAirEvents(const glm::dvec3& o, const glm::dvec3& d, double t_start,
                     Event* best) const;
  void WaterEvents(const glm::dvec3& o, const glm::dvec3& d, Event* best) const;
  void GlassEvents(const glm::dvec3& o, const glm::dvec3& d, Event* best) const;
  void BoardHit(const glm::dvec3& o, const glm::dvec3& d, double t,
                Event* best) const;
  int AddChart(double u_size, double v_size, double texel, bool wrap_u);

  bool wet_ = false;
  double a_ = 0, b_ = 0, A_ = 0, B_ = 0, H_ = 0;
  double ior_[3] = {1.0, 1.333, 1.5};
  glm::dvec3 light_{0, 0, 1};
  double alpha_ = 0;
  Spectrum sigma_{0.0};
  WaterSurface surface_;
  std::vector<Solid> solids_;
  std::vector<Chart> charts_;
  cv::Rect2d board_rect_;
  // Albedo texture.
  cv::Mat albedo_;
  cv::Rect2d albedo_rect_;
  Spectrum table_{0.3};
  ReferenceScene::Room room_;
};

}  // namespace ripple::reference::internal

#endif  // RIPPLE_RENDER_REFERENCE_SCENE_MODEL_H_
