// Shadow pass (internal to render/): a depth map of the occluders (obstacles,
// pen; the glass walls transmit) seen from the directional light, fitted to the
// tank, and the receiver map the water samples instead of a PCF kernel per
// pixel: r = light reaching the floor, g = light reaching the surface at rest.
//
// Redraw key (ShadowKey): the tank geometry, the light direction, whether
// the pen is visible, its geometry and pose (when it casts:
// RendererOptions::pen_casts_shadow), and each obstacle's shape, size and
// pose; poses count as moved beyond RendererOptions'
// shadow_move_threshold_m / shadow_turn_threshold_rad. The light is fixed in
// the tank frame, so the camera moving never redraws it.
#ifndef RIPPLE_RENDER_PASS_SHADOW_H_
#define RIPPLE_RENDER_PASS_SHADOW_H_

#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/meshes.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace ripple::render::internal {

// What the shadow map was last drawn from.
struct ShadowKey {
  bool pen_visible = false;
  glm::dmat4 tank_from_pen{1.0};
  PenGeometry pen;
  std::vector<Obstacle> obstacles;
  glm::dvec3 light{0.0};  // unit
  TankGeometry tank;

  static ShadowKey Of(const SceneInputs& scene);
  // True if `scene` would draw a visibly different map: something changed,
  // or a pose moved by more than `move_m` (metres) or turned by more than
  // `turn_rad` (radians).
  // `with_pen`: the pen is one of the casters.
  bool Differs(const SceneInputs& scene, double move_m, double turn_rad,
               bool with_pen) const;
};

// The #defines that select `filter` in the programs calling Shadow()
// (common.glsl): SHADOW_FILTER_GAUSS with its tap weight, SHADOW_FILTER_HARD,
// nothing for PCF. `sigma_texels`: kGauss's standard deviation.
std::string ShadowFilterDefines(ShadowFilter filter, float sigma_texels);
// kGauss's tap spacing, map texels: clamp(sigma, 1, 2), so the taps'
// bilinear footprints overlap (a smooth edge) and span 4x4 to 6x6 texels.
double GaussTapSpacingTexels(float sigma_texels);

// The orthographic light frame fitted to the tank box (receivers) with room
// for casters up to a metre towards the light.
ShadowTransform FitShadowFrustum(const TankGeometry& tank,
                                 const glm::dvec3& light);

class ShadowPass {
 public:
  struct Options {
    int map_size = 512;  // texels per side
    double move_threshold_m = 0.001;
    double turn_threshold_rad = 0.0087;
    bool pen = true;  // the pen casts (RendererOptions::pen_casts_shadow)
    ShadowFilter filter = ShadowFilter::kPcf;
    float gauss_sigma_texels = 1.5f;  // kGauss
  };
  bool Create(const Options& options, std::string* error);

  bool NeedsRedraw(const SceneInputs& scene) const;
  // Redraws the maps for `f` (f.height must be this frame's) and records
  // the key.
  void Draw(const FrameState& f, const SolidMeshes& solids);

  const ShadowTransform& transform() const { return transform_; }
  GLuint shadow_texture() const { return shadow_tex_.id(); }
  GLuint receiver_texture() const { return receiver_tex_.id(); }

 private:
  Options options_;
  Program depth_, receiver_;
  ModelUniforms depth_model_;
  CommonUniforms receiver_common_;
  VertexArray empty_vao_;
  Texture shadow_tex_, receiver_tex_;
  Framebuffer shadow_fbo_, receiver_fbo_;
  std::optional<ShadowKey> key_;
  ShadowTransform transform_;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_SHADOW_H_
