// Water pass (internal to render/): the surface mesh lays its depth and
// marks its visible pixels in the stencil, then one full-screen shading per
// marked pixel (refraction, shadow, caustics, reflection, specular) inside
// the water's window rectangle.
//
// llvmpipe executes both sides of every branch, so each combination of
// effects is its own program; all of them are compiled at creation.
//
// Redraw key: none (the output is redrawn every frame). The floor-return
// map: traced when the tank changes; its surroundings' light re-uploaded
// when the board's radiance beyond a wall, read from the video, changes.
#ifndef RIPPLE_RENDER_PASS_WATER_H_
#define RIPPLE_RENDER_PASS_WATER_H_

#include <glm/glm.hpp>
#include <optional>
#include <string>

#include "render/frame_state.h"
#include "render/gl_objects.h"
#include "render/optics.h"
#include "render/pass_real.h"

namespace ripple::render::internal {

class WaterPass {
 public:
  struct Options {
    int surface_grid = 8;  // quads per side of the surface mesh
    WaterOptics optics;
    float reflection_distance_m = 0.3f;
    // Every variant: the reflection from the environment cube map
    // (pass_envmap.h) rather than the fold; the daylight sky over it.
    bool env_cube = false;
    bool sky = false;
    // Shade the real pen, the clean plate and the mirror only inside their
    // regions (water_regions.h) and the rest of the water without them; the
    // output is the same. false: every water pixel takes every effect.
    bool regions = true;
  };
  bool Create(const Options& options, std::string* error);

  // Draws into the bound output (depth laid by earlier passes), with the
  // frame's textures bound to their units. `have_video`: the reflection map
  // holds something; `real`: the real pen and the plate (RealObjectsPass).
  void Draw(const FrameState& f, bool have_video, const RealObjectsState& real);
  // The return's ratio of the bands to green (see UpdateFloorReturn).
  const glm::vec3& return_tint() const { return return_tint_; }

  // Texels of the floor-return map (optics.h) over the tank floor, and the
  // directions traced per texel; recomputed when the tank changes.
  static constexpr int kReturnNx = 32, kReturnNy = 21, kReturnRays = 512;

 private:
  // Variant bits: one program per combination of these effects.
  enum Variant : int {
    kShadows = 1,
    kCaustics = 2,
    kReflection = 4,
    kRefraction = 8,
    // Only with kRefraction (RealObjectsState): the submerged real pen, and
    // the clean plate behind this frame's occluder mask.
    kRealPen = 16,
    kRealPlate = 32,
    // Only with kReflection: the mirrored obstacles and pen (pass_mirror.h).
    kMirror = 64,
    kVariants = 128,
  };
  struct Shading {
    Program program;
    CommonUniforms common;
    // Per-frame optics (FrameState::shading).
    GLint floor_sky = -1, floor_sun = -1, inv_n2 = -1, glass_t = -1,
          glint_peak = -1, inv_alpha2 = -1, return_tint = -1;
    // kRealPen, kRealPlate.
    GLint pen_tip = -1, pen_axis = -1, pen_length = -1, pen_radius = -1,
          pen_margin = -1, plate_map = -1, plate_gain = -1;
  };
  bool BuildShading(Shading* s, const std::string& defines,
                    const Options& options, std::string* error);
  // Binds `s` and sets the frame's uniforms.
  void Prepare(const Shading& s, const FrameState& f,
               const RealObjectsState& real) const;

  // The floor-return map for the frame's tank (traced on the CPU, once per
  // tank) and its surroundings' light for the board's radiance beyond each
  // wall as this frame's video shows it (re-uploaded when that changes).
  void UpdateFloorReturn(const FrameState& f);
  // Changes of the board's radiance below this leave the map as it is.
  static constexpr float kBoardChange = 0.002f;

  Options options_;
  FloorReturnMap floor_return_;
  Texture floor_return_tex_;  // RGBA: surroundings' light, green return
  glm::vec3 return_tint_{1.0f};
  std::optional<TankGeometry> floor_return_tank_;
  glm::vec3 board_radiance_[4] = {glm::vec3(0.0f), glm::vec3(0.0f),
                                  glm::vec3(0.0f), glm::vec3(0.0f)};
  bool uploaded_ = false;
  Shading variants_[kVariants];
  Shading flat_;  // Effects::flat_water: one colour, whatever the effects
  Program depth_;
  CommonUniforms depth_common_;
  VertexArray grid_vao_, empty_vao_;
  Buffer grid_vbo_, grid_ibo_;
  int grid_index_count_ = 0;
};

}  // namespace ripple::render::internal

#endif  // RIPPLE_RENDER_PASS_WATER_H_
