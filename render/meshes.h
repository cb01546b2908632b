// The solid meshes the passes share (internal to render/): the unit box and
// cylinder that obstacles and the pen are drawn from, and the tank's four
// walls. Vertices: attribute 0 position, 1 normal (walls: 2 the wall
// coordinate), tank or model frame, metres.
#ifndef RIPPLE_RENDER_MESHES_H_
#define RIPPLE_RENDER_MESHES_H_

#include <glm/glm.hpp>
#include <optional>

#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

struct Mesh {
  VertexArray vao;
  Buffer vbo;
  int count = 0;  // vertices, drawn as GL_TRIANGLES
};

// Locations of solid.vert's model transforms in one program.
struct ModelUniforms {
  GLint tank_from_model = -1;
  GLint clip_from_model = -1;
  void Resolve(const Program& p);
};

// The glass walls as 4 x 6 vertices (wall i: vertices 6i..6i+5; walls run
// counter-clockwise seen from above, starting with the -y wall) at the inner
// size, then their top faces as 4 x 6 vertices (24..47: the ring at the wall
// height out to the glass's outer faces, `glass_thickness_m` beyond; their
// normal slot the direction across the wall away from the face, their uv
// slot the wall's inward normal).
// Rebuilt only when the tank geometry changes (its redraw key).
class TankWallsMesh {
 public:
  static constexpr int kTopFirst = 24, kTopCount = 24;
  void Create(float glass_thickness_m);
  void Update(const TankGeometry& tank);
  GLuint vao() const { return vao_.id(); }

 private:
  VertexArray vao_;
  Buffer vbo_;
  std::optional<TankGeometry> tank_;
  float glass_thickness_m_ = 0;
};

// How far the pen is drawn out from its size on every side, metres: the
// cube, and the shaft's radius and its length at the tip (negative shrinks
// the radius only).
struct PenGrow {
  double cube_m = 0;
  double shaft_m = 0;
};

class SolidMeshes {
 public:
  void Create();
  // Draws the scene's obstacles and/or the pen (cube and shaft, grown by
  // `pen_grow`) with the bound program `p` (solid.vert) projected by
  // `clip_from_tank`.
  void Draw(const SceneInputs& scene, const ModelUniforms& p,
            const glm::dmat4& clip_from_tank, bool obstacles, bool pen,
            const PenGrow& pen_grow = {}) const;

 private:
  Mesh box_, cylinder_;
};

bool SameTank(const TankGeometry& a, const TankGeometry& b);

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_MESHES_H_
