// Caustics pass (internal to render/): drives ComputeCaustics on the CPU and
// uploads the floor irradiance map (relative to flat water) as a texture.
//
// Redraw key (CausticsKey): the height field's change counter (or "flat"
// for null heights), the light direction and the tank geometry.
#ifndef RIPPLE_RENDER_PASS_CAUSTICS_H_
#define RIPPLE_RENDER_PASS_CAUSTICS_H_

#include <cstdint>
#include <glm/glm.hpp>
#include <optional>
#include <vector>

#include "render/caustics.h"
#include "render/gl_objects.h"
#include "render/scene.h"

namespace ripple::render::internal {

struct CausticsKey {
  std::optional<std::uint64_t> counter;  // nullopt: flat water
  glm::dvec3 light{0.0};                 // unit
  TankGeometry tank;

  static CausticsKey Of(const SceneInputs& scene);
  bool Same(const CausticsKey& o) const;
};

class CausticsPass {
 public:
  // `options.map_nx` == `options.map_ny` (a square texture over the floor);
  // renderer.h, CausticsOptionsFor.
  void Create(const CausticsOptions& options);

  // Recomputes the map on the CPU if its key changed since it was last
  // computed; true if it did, with the CPU time in `ms`. No GL: it may run
  // on another thread while the GL thread does not call Update.
  bool Trace(const SceneInputs& scene, double* ms);
  // Trace, then uploads a map not uploaded yet (GL thread); true if it
  // traced.
  bool Update(const SceneInputs& scene, double* ms);
  GLuint texture() const { return texture_.id(); }
  // The map's mean over the floor (1 before the first trace): the surface
  // moves the light it lets in, the walls add theirs (the strip beside the
  // walls facing the light, the glass's reflections), so with walls it is
  // above 1.
  float mean() const { return mean_; }

 private:
  CausticsOptions options_;
  Texture texture_;
  std::vector<float> map_;
  float mean_ = 1.0f;
  CausticsWorkspace workspace_;
  std::optional<CausticsKey> key_;  // of map_
  bool uploaded_ = false;           // map_ is in texture_
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_CAUSTICS_H_
